#pragma once
// Synthetic calibration data for the tests: a known Kinect1-like camera, random board poses it sees,
// corners projected by cv::projectPoints with Gaussian noise, boards rendered by warpPerspective, and
// noisy tracker poses. Everything is drawn from a seeded std::mt19937.
#include <opencv2/core.hpp>

#include <random>
#include <vector>

#include "calibrate/board.h"
#include "core/camera.h"
#include "core/rigid3.h"

namespace mocap::test {

/// 640x480, fx 525.3, fy 524.1, cx 319.2, cy 241.7, k1 0.16, k2 -0.42, p1 0.0012, p2 -0.0009, k3 0.25.
PinholeCamera Kinect1Camera();
/// The tests' ChArUco board: 8x6 squares of 40 mm (0.32 x 0.24 m), 30 mm DICT_5X5_100 markers.
BoardSpec TestBoard(BoardType type = BoardType::kCharuco);
/// The intrinsics tests' board: 12x9 squares of 40 mm (0.48 x 0.36 m), 30 mm markers. A board a third
/// of the image wide leaves fx uncertain to about 0.4 % (1-sigma) with 40 views at 0.2 px noise.
BoardSpec LargeBoard();

Eigen::Quaterniond ExpSO3(const Eigen::Vector3d& rvec_rad);
/// T perturbed by Gaussian rotation (deg, per axis, applied on the left) and translation (m, per axis).
Rigid3d Noisy(const Rigid3d& T, std::mt19937& rng, double sigma_m, double sigma_deg);

/// A board pose that puts the board's centre on a uniformly drawn pixel at a depth in [min_z, max_z],
/// tilted away from facing the camera by a uniform angle in [min_tilt_deg, max_tilt_deg] about a random
/// axis, turned in its plane by up to +-180 deg.
Rigid3d RandomBoardPose(std::mt19937& rng, const PinholeCamera& camera, const BoardSpec& spec, double min_z_m,
                        double max_z_m, double min_tilt_deg, double max_tilt_deg);

/// The corners that project inside the image (5 px margin) by cv::projectPoints, with N(0, noise_px)
/// added per axis; `failure` set when fewer than min_corners project inside.
BoardDetection ProjectBoard(const PinholeCamera& camera, const BoardSpec& spec, const Rigid3d& T_camera_board,
                            double noise_px, std::mt19937& rng, int min_corners = 8);

/// `count` random board poses whose projection holds at least min_corners corners.
std::vector<Rigid3d> VisibleBoardPoses(std::mt19937& rng, const PinholeCamera& camera, const BoardSpec& spec, int count,
                                       double min_z_m, double max_z_m, double min_tilt_deg, double max_tilt_deg,
                                       int min_corners);

/// Renders the board (DrawBoard) as a distortion-free camera with matrix K sees it at T_camera_board:
/// warpPerspective of the board image at 3x supersampling, then area-averaged down to `size`,
/// on a mid-grey background. Returns the 8-bit grey image.
cv::Mat RenderBoard(const BoardSpec& spec, const Eigen::Matrix3d& K, const Rigid3d& T_camera_board, cv::Size size);

/// Pixel of a board-frame point through the homography of a distortion-free camera K.
Eigen::Vector2d ProjectPlanar(const Eigen::Matrix3d& K, const Rigid3d& T_camera_board, const Eigen::Vector3d& p_board);

/// The truth of the mount tests: camera optical frame on its body (markers above the Kinect), board on
/// its body.
inline const Rigid3d kCambodyCamera(ExpSO3(Eigen::Vector3d(0.35, -0.20, 1.40)), Eigen::Vector3d(0.032, -0.081, 0.024));
inline const Rigid3d kBoardbodyBoard(ExpSO3(Eigen::Vector3d(-0.10, 0.25, -1.57)),
                                     Eigen::Vector3d(-0.052, 0.247, -0.012));

}  // namespace mocap::test
