#pragma once
// Calibration boards: their geometry, their printable image and their detection in a camera image.
//
// The board frame (both types): origin at the bottom-left outer corner of the board as printed (as
// DrawBoard draws it, upright), x to the right along the columns, y up along the rows, z out of the
// printed face towards whoever looks at it; metres. The board lies in z = 0.
// Inner corner `id` (row r counted from the top, column c from the left, id = r * (squares_x - 1) + c)
// sits at ((c + 1) * square_m, (squares_y - 1 - r) * square_m, 0).
// OpenCV 4.6 (Debian 12) puts the ChArUco origin at the top-left corner, y down, z into the board: its corner
// (x, y, 0) is our (x, squares_y * square_m - y, 0), a half turn about x; corner ids are the same.
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/core.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace mocap {

enum class BoardType : uint8_t { kCharuco = 0, kCheckerboard = 1 };
std::string_view ToString(BoardType type);
/// "charuco" or "checkerboard"; throws InputError otherwise.
BoardType BoardTypeFromString(std::string_view name);

struct BoardSpec {
  BoardType type = BoardType::kCharuco;
  int squares_x = 8;       ///< squares along x (columns); inner corners: squares_x - 1
  int squares_y = 6;       ///< squares along y (rows)
  double square_m = 0.04;  ///< side of one chessboard square, metres
  double marker_m = 0.03;  ///< side of one ArUco marker (ChArUco only), metres
  std::string dictionary = "DICT_5X5_100";  ///< OpenCV predefined dictionary name (ChArUco only)

  /// Throws InputError naming the field: squares below 3, a non-positive or over-large square, a marker
  /// not smaller than its square, an unknown dictionary or one with fewer markers than the board needs.
  void check() const;
  int corners_x() const { return squares_x - 1; }
  int corners_y() const { return squares_y - 1; }
  int corner_count() const { return corners_x() * corners_y(); }
  double width_m() const { return squares_x * square_m; }
  double height_m() const { return squares_y * square_m; }
};

/// The inner corners in the board frame (metres), indexed by corner id. Precondition: spec checked.
std::vector<Eigen::Vector3d> BoardCornerPoints(const BoardSpec& spec);

/// OpenCV's predefined dictionary id for a name such as "DICT_5X5_100"; throws InputError when unknown.
int ArucoDictionaryId(std::string_view name);

/// The OpenCV board (OpenCV's own frame, see above). Precondition: spec checked, type ChArUco.
cv::Ptr<cv::aruco::CharucoBoard> MakeCharucoBoard(const BoardSpec& spec);

/// A printable board image and where the board frame lies in it.
struct BoardImage {
  cv::Mat gray;  ///< CV_8UC1, white margin around the board
  /// Maps board-frame metres (x, y, 1) to pixels (u, v, 1) of `gray` (OpenCV pixel convention). A
  /// simulator texture maps through it; H_image_board of a view is then H_image_texture * H_pixel_board.
  Eigen::Matrix3d H_pixel_board;
};

/// Draws the board with `pixels_per_square` pixels per square and a white margin of `margin_px`.
/// Throws InputError when pixels_per_square < 8 or margin_px < 0 (and when the spec is invalid).
BoardImage DrawBoard(const BoardSpec& spec, int pixels_per_square, int margin_px);

/// The board corners found in one image.
struct BoardDetection {
  std::vector<int> corner_ids;              ///< ids into BoardCornerPoints()
  std::vector<Eigen::Vector2d> corners_px;  ///< sub-pixel positions, OpenCV pixel convention
  int markers_found = 0;                    ///< ArUco markers decoded (ChArUco only)
  std::string failure;                      ///< why no board was found; empty when found
  bool found() const { return failure.empty(); }
};

/// Finds the board in an 8-bit grey (or BGR) image. ChArUco: cv::aruco::detectMarkers and
/// interpolateCornersCharuco, then cv::cornerSubPix with a window that stays clear of the markers
/// (OpenCV 4.6's own refinement leaves a bias of about half a pixel). Checkerboard:
/// cv::findChessboardCornersSB (all corners or none; its corner order can start at either end, so
/// the pose of a checkerboard is ambiguous under a half turn). Fewer than `min_corners` corners is a
/// failure with its reason. Throws InputError on an empty image or one that is not 8-bit.
BoardDetection DetectBoard(const cv::Mat& image, const BoardSpec& spec, int min_corners = 6);

}  // namespace mocap
