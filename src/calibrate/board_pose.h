#pragma once
// The board's pose in the camera from one detection, and the reprojection residuals of a board pose.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "calibrate/board.h"
#include "core/camera.h"
#include "core/rigid3.h"

namespace mocap {

struct BoardPose {
  Rigid3d T_camera_board;
  double rms_px = 0;  ///< reprojection RMS of the detected corners at this pose
};

/// cv::solvePnP (IPPE, for planar targets) then cv::solvePnPRefineLM on the detected corners.
/// Empty when fewer than 4 corners were detected, when solvePnP fails, or when the board would lie
/// behind the camera. Precondition: spec and camera checked, corner ids within the board.
std::optional<BoardPose> EstimateBoardPose(const BoardDetection& detection, const BoardSpec& spec,
                                           const PinholeCamera& camera);

/// Per-corner reprojection error (pixels, detected minus projected) of the board at T_camera_board;
/// a corner that projects behind the camera gets an error of 1e6 px.
std::vector<Eigen::Vector2d> ReprojectionErrorsPx(const BoardDetection& detection,
                                                  const std::vector<Eigen::Vector3d>& points_board,
                                                  const PinholeCamera& camera, const Rigid3d& T_camera_board);

/// Root mean square of the error norms; 0 for none.
double RmsPx(const std::vector<Eigen::Vector2d>& errors_px);

}  // namespace mocap
