#include "calibrate/board.h"

#include <opencv2/aruco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "core/check.h"

namespace mocap {
namespace {

constexpr std::array<std::pair<std::string_view, int>, 21> kDictionaries = {{
    {"DICT_4X4_50", cv::aruco::DICT_4X4_50},         {"DICT_4X4_100", cv::aruco::DICT_4X4_100},
    {"DICT_4X4_250", cv::aruco::DICT_4X4_250},       {"DICT_4X4_1000", cv::aruco::DICT_4X4_1000},
    {"DICT_5X5_50", cv::aruco::DICT_5X5_50},         {"DICT_5X5_100", cv::aruco::DICT_5X5_100},
    {"DICT_5X5_250", cv::aruco::DICT_5X5_250},       {"DICT_5X5_1000", cv::aruco::DICT_5X5_1000},
    {"DICT_6X6_50", cv::aruco::DICT_6X6_50},         {"DICT_6X6_100", cv::aruco::DICT_6X6_100},
    {"DICT_6X6_250", cv::aruco::DICT_6X6_250},       {"DICT_6X6_1000", cv::aruco::DICT_6X6_1000},
    {"DICT_7X7_50", cv::aruco::DICT_7X7_50},         {"DICT_7X7_100", cv::aruco::DICT_7X7_100},
    {"DICT_7X7_250", cv::aruco::DICT_7X7_250},       {"DICT_7X7_1000", cv::aruco::DICT_7X7_1000},
    {"DICT_ARUCO_ORIGINAL", cv::aruco::DICT_ARUCO_ORIGINAL},
    {"DICT_APRILTAG_16h5", cv::aruco::DICT_APRILTAG_16h5}, {"DICT_APRILTAG_25h9", cv::aruco::DICT_APRILTAG_25h9},
    {"DICT_APRILTAG_36h10", cv::aruco::DICT_APRILTAG_36h10}, {"DICT_APRILTAG_36h11", cv::aruco::DICT_APRILTAG_36h11},
}};

BoardDetection Failure(std::string reason, int markers_found = 0) {
  BoardDetection detection;
  detection.failure = std::move(reason);
  detection.markers_found = markers_found;
  return detection;
}

cv::Mat ToGray(const cv::Mat& image) {
  if (image.empty()) throw InputError("DetectBoard", "the image is empty");
  if (image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3))
    throw InputError("DetectBoard", Str("need an 8-bit grey or BGR image, got type ", image.type()));
  if (image.channels() == 1) return image;
  cv::Mat gray;
  cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  return gray;
}

/// Half-size (pixels) of a cornerSubPix window around `corner` that keeps the nearest marker corners
/// (at +-gap along both board axes) outside: Chebyshev distance of their images, times 0.85.
int SubPixHalfWindow(const cv::Matx33d& H_image_board, const Eigen::Vector3d& corner, double gap_m) {
  auto project = [&](double x, double y) {
    const cv::Vec3d p = H_image_board * cv::Vec3d(x, y, 1.0);
    return cv::Point2d(p[0] / p[2], p[1] / p[2]);
  };
  const cv::Point2d centre = project(corner.x(), corner.y());
  double nearest_px = 1e9;
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0}) {
      const cv::Point2d d = project(corner.x() + sx * gap_m, corner.y() + sy * gap_m) - centre;
      nearest_px = std::min(nearest_px, std::max(std::abs(d.x), std::abs(d.y)));
    }
  return std::clamp(static_cast<int>(std::floor(0.85 * nearest_px)), 2, 10);
}

/// cv::cornerSubPix on every corner with a window that keeps clear of the nearest other feature,
/// gap_m away along both board axes (a marker's corner on a ChArUco board, the next corner on a
/// checkerboard).
void RefineCorners(const cv::Mat& gray, const BoardSpec& spec, double gap_m, BoardDetection& detection) {
  const std::vector<Eigen::Vector3d> points_board = BoardCornerPoints(spec);
  std::vector<cv::Point2d> xy_board, uv_image;
  for (size_t i = 0; i < detection.corner_ids.size(); ++i) {
    const Eigen::Vector3d& p = points_board[static_cast<size_t>(detection.corner_ids[i])];
    xy_board.emplace_back(p.x(), p.y());
    uv_image.emplace_back(detection.corners_px[i].x(), detection.corners_px[i].y());
  }
  const cv::Mat H = cv::findHomography(xy_board, uv_image);
  if (H.empty()) return;  // degenerate corner layout: keep OpenCV's corners
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-4);
  for (size_t i = 0; i < detection.corner_ids.size(); ++i) {
    const int half = SubPixHalfWindow(cv::Matx33d(H), points_board[static_cast<size_t>(detection.corner_ids[i])], gap_m);
    std::vector<cv::Point2f> corner = {cv::Point2f(uv_image[i])};
    cv::cornerSubPix(gray, corner, cv::Size(half, half), cv::Size(-1, -1), stop);
    const Eigen::Vector2d refined(corner[0].x, corner[0].y);
    if ((refined - detection.corners_px[i]).norm() < half) detection.corners_px[i] = refined;
  }
}

BoardDetection DetectCharuco(const cv::Mat& gray, const BoardSpec& spec, int min_corners) {
  const cv::Ptr<cv::aruco::CharucoBoard> board = MakeCharucoBoard(spec);
  std::vector<std::vector<cv::Point2f>> marker_corners;
  std::vector<int> marker_ids;
  cv::aruco::detectMarkers(gray, board->dictionary, marker_corners, marker_ids);
  const int markers = static_cast<int>(marker_ids.size());
  if (markers == 0) return Failure(Str("no ArUco marker of ", spec.dictionary, " found"));
  std::vector<cv::Point2f> corners;
  std::vector<int> ids;
  cv::aruco::interpolateCornersCharuco(marker_corners, marker_ids, gray, board, corners, ids);
  if (static_cast<int>(ids.size()) < min_corners)
    return Failure(Str("only ", ids.size(), " chessboard corners found next to ", markers, " markers (need ",
                       min_corners, ")"), markers);
  BoardDetection detection;
  detection.markers_found = markers;
  detection.corner_ids = ids;
  for (const cv::Point2f& c : corners) detection.corners_px.emplace_back(c.x, c.y);
  RefineCorners(gray, spec, 0.5 * (spec.square_m - spec.marker_m), detection);
  return detection;
}

BoardDetection DetectCheckerboard(const cv::Mat& gray, const BoardSpec& spec, int min_corners) {
  std::vector<cv::Point2f> corners;
  const cv::Size pattern(spec.corners_x(), spec.corners_y());
  if (!cv::findChessboardCornersSB(gray, pattern, corners, cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY))
    return Failure(Str("no checkerboard of ", pattern.width, "x", pattern.height,
                       " inner corners found (all of them must be in view)"));
  if (static_cast<int>(corners.size()) < min_corners)
    return Failure(Str("only ", corners.size(), " corners (need ", min_corners, ")"));
  BoardDetection detection;
  for (size_t i = 0; i < corners.size(); ++i) {
    detection.corner_ids.push_back(static_cast<int>(i));
    detection.corners_px.emplace_back(corners[i].x, corners[i].y);
  }
  RefineCorners(gray, spec, 0.5 * spec.square_m, detection);
  return detection;
}

void DrawCheckerboard(const BoardSpec& spec, int pixels_per_square, int margin_px, cv::Mat& gray) {
  gray.setTo(255);
  for (int row = 0; row < spec.squares_y; ++row)
    for (int col = 0; col < spec.squares_x; ++col)
      if ((row + col) % 2 == 0)
        gray(cv::Rect(margin_px + col * pixels_per_square, margin_px + row * pixels_per_square, pixels_per_square,
                      pixels_per_square)).setTo(0);
}

}  // namespace

std::string_view ToString(BoardType type) { return type == BoardType::kCharuco ? "charuco" : "checkerboard"; }

BoardType BoardTypeFromString(std::string_view name) {
  if (name == "charuco") return BoardType::kCharuco;
  if (name == "checkerboard") return BoardType::kCheckerboard;
  throw InputError("board.type", Str("unknown board type \"", name, "\"; use charuco or checkerboard"));
}

int ArucoDictionaryId(std::string_view name) {
  for (const auto& [known, id] : kDictionaries)
    if (known == name) return id;
  throw InputError("board.dictionary", Str("unknown ArUco dictionary \"", name, "\"; e.g. DICT_5X5_100"));
}

void BoardSpec::check() const {
  if (squares_x < 3) throw InputError("board.squares_x", Str("is ", squares_x, "; need at least 3 squares"));
  if (squares_y < 3) throw InputError("board.squares_y", Str("is ", squares_y, "; need at least 3 squares"));
  if (!(square_m > 0 && square_m <= 1))
    throw InputError("board.square_m", Str("is ", square_m, "; must lie in (0, 1] metres (is it in mm?)"));
  if (type != BoardType::kCharuco) return;
  if (!(marker_m > 0 && marker_m < square_m))
    throw InputError("board.marker_m", Str("is ", marker_m, "; must be positive and smaller than square_m (", square_m, ")"));
  const int markers_needed = squares_x * squares_y / 2;
  const int markers_known = cv::aruco::getPredefinedDictionary(ArucoDictionaryId(dictionary))->bytesList.rows;
  if (markers_needed > markers_known)
    throw InputError("board.dictionary", Str(dictionary, " holds ", markers_known, " markers; the board needs ",
                                             markers_needed));
}

std::vector<Eigen::Vector3d> BoardCornerPoints(const BoardSpec& spec) {
  std::vector<Eigen::Vector3d> points_board;
  points_board.reserve(static_cast<size_t>(spec.corner_count()));
  for (int row = 0; row < spec.corners_y(); ++row)
    for (int col = 0; col < spec.corners_x(); ++col)
      points_board.emplace_back((col + 1) * spec.square_m, (spec.squares_y - 1 - row) * spec.square_m, 0.0);
  return points_board;
}

cv::Ptr<cv::aruco::CharucoBoard> MakeCharucoBoard(const BoardSpec& spec) {
  MOCAP_CHECK(spec.type == BoardType::kCharuco, "MakeCharucoBoard on a checkerboard");
  return cv::aruco::CharucoBoard::create(spec.squares_x, spec.squares_y, static_cast<float>(spec.square_m),
                                         static_cast<float>(spec.marker_m),
                                         cv::aruco::getPredefinedDictionary(ArucoDictionaryId(spec.dictionary)));
}

BoardImage DrawBoard(const BoardSpec& spec, int pixels_per_square, int margin_px) {
  spec.check();
  if (pixels_per_square < 8) throw InputError("DrawBoard", Str("pixels_per_square is ", pixels_per_square, "; need >= 8"));
  if (margin_px < 0) throw InputError("DrawBoard", Str("margin_px is ", margin_px, "; must be >= 0"));
  const cv::Size size(spec.squares_x * pixels_per_square + 2 * margin_px, spec.squares_y * pixels_per_square + 2 * margin_px);
  BoardImage out;
  out.gray = cv::Mat(size, CV_8UC1);
  if (spec.type == BoardType::kCharuco)
    MakeCharucoBoard(spec)->draw(size, out.gray, margin_px, 1);
  else
    DrawCheckerboard(spec, pixels_per_square, margin_px, out.gray);
  // Pixel centres at integers: the board's left edge is at u = margin - 0.5, its top edge (y = height)
  // at v = margin - 0.5.
  const double px_per_m = pixels_per_square / spec.square_m;
  const double origin = margin_px - 0.5;
  out.H_pixel_board << px_per_m, 0, origin, 0, -px_per_m, origin + spec.height_m() * px_per_m, 0, 0, 1;
  return out;
}

BoardDetection DetectBoard(const cv::Mat& image, const BoardSpec& spec, int min_corners) {
  spec.check();
  if (min_corners < 4) throw InputError("DetectBoard", Str("min_corners is ", min_corners, "; need >= 4"));
  const cv::Mat gray = ToGray(image);
  return spec.type == BoardType::kCharuco ? DetectCharuco(gray, spec, min_corners)
                                          : DetectCheckerboard(gray, spec, min_corners);
}

}  // namespace mocap
