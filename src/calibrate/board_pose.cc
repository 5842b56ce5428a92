#include "calibrate/board_pose.h"

#include <opencv2/calib3d.hpp>

#include <cmath>

#include "calibrate/cv_convert.h"

namespace mocap {

std::optional<BoardPose> EstimateBoardPose(const BoardDetection& detection, const BoardSpec& spec,
                                           const PinholeCamera& camera) {
  if (detection.corner_ids.size() < 4) return std::nullopt;
  const std::vector<Eigen::Vector3d> points_board = BoardCornerPoints(spec);
  const std::vector<cv::Point3f> object = CvObjectPoints(detection, points_board);
  const std::vector<cv::Point2f> image = CvImagePoints(detection);
  const cv::Mat K = CvCameraMatrix(camera), dist = CvDistCoeffs(camera);
  cv::Mat rvec, tvec;
  try {
    if (!cv::solvePnP(object, image, K, dist, rvec, tvec, false, cv::SOLVEPNP_IPPE)) return std::nullopt;
    cv::solvePnPRefineLM(object, image, K, dist, rvec, tvec);
  } catch (const cv::Exception&) {
    return std::nullopt;  // degenerate (collinear) corners
  }
  BoardPose pose;
  pose.T_camera_board = RigidFromCv(cv::Vec3d(rvec), cv::Vec3d(tvec));
  if (pose.T_camera_board.translation().z() <= 0) return std::nullopt;
  pose.rms_px = RmsPx(ReprojectionErrorsPx(detection, points_board, camera, pose.T_camera_board));
  return pose;
}

std::vector<Eigen::Vector2d> ReprojectionErrorsPx(const BoardDetection& detection,
                                                  const std::vector<Eigen::Vector3d>& points_board,
                                                  const PinholeCamera& camera, const Rigid3d& T_camera_board) {
  std::vector<Eigen::Vector2d> errors;
  errors.reserve(detection.corner_ids.size());
  for (size_t i = 0; i < detection.corner_ids.size(); ++i) {
    const Eigen::Vector3d p_camera = T_camera_board * points_board[static_cast<size_t>(detection.corner_ids[i])];
    const std::optional<Eigen::Vector2d> projected = camera.Project(p_camera);
    errors.push_back(projected ? Eigen::Vector2d(detection.corners_px[i] - *projected) : Eigen::Vector2d(1e6, 0));
  }
  return errors;
}

double RmsPx(const std::vector<Eigen::Vector2d>& errors_px) {
  if (errors_px.empty()) return 0;
  double sum = 0;
  for (const Eigen::Vector2d& e : errors_px) sum += e.squaredNorm();
  return std::sqrt(sum / static_cast<double>(errors_px.size()));
}

}  // namespace mocap
