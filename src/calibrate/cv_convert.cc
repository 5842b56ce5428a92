#include "calibrate/cv_convert.h"

#include <opencv2/calib3d.hpp>

#include "core/check.h"

namespace mocap {

cv::Mat CvCameraMatrix(const PinholeCamera& camera) {
  return (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
}

cv::Mat CvDistCoeffs(const PinholeCamera& camera) {
  cv::Mat dist(1, 8, CV_64F);
  for (int i = 0; i < 8; ++i) dist.at<double>(i) = camera.dist[static_cast<size_t>(i)];
  return dist;
}

PinholeCamera CameraFromCv(const cv::Mat& K, const cv::Mat& dist, cv::Size image_size) {
  MOCAP_CHECK(K.rows == 3 && K.cols == 3 && K.type() == CV_64F, "K must be 3x3 CV_64F");
  PinholeCamera camera;
  camera.width = image_size.width;
  camera.height = image_size.height;
  camera.fx = K.at<double>(0, 0);
  camera.fy = K.at<double>(1, 1);
  camera.cx = K.at<double>(0, 2);
  camera.cy = K.at<double>(1, 2);
  cv::Mat d;
  dist.convertTo(d, CV_64F);
  d = d.reshape(1, 1);
  for (int i = 0; i < d.cols; ++i) {
    if (i < 8) camera.dist[static_cast<size_t>(i)] = d.at<double>(i);
    else MOCAP_CHECK(d.at<double>(i) == 0.0, "thin-prism or tilt coefficients are not part of PinholeCamera");
  }
  return camera;
}

Rigid3d RigidFromCv(const cv::Vec3d& rvec, const cv::Vec3d& tvec_m) {
  return Rigid3d::FromRvec(Eigen::Vector3d(rvec[0], rvec[1], rvec[2]), Eigen::Vector3d(tvec_m[0], tvec_m[1], tvec_m[2]));
}

void CvFromRigid(const Rigid3d& T, cv::Vec3d& rvec, cv::Vec3d& tvec_m) {
  const Eigen::Vector3d r = T.rvec();
  rvec = cv::Vec3d(r.x(), r.y(), r.z());
  tvec_m = cv::Vec3d(T.translation().x(), T.translation().y(), T.translation().z());
}

cv::Matx33d CvRotation(const Rigid3d& T) {
  const Eigen::Matrix3d R = T.rotation_matrix();
  cv::Matx33d out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out(r, c) = R(r, c);
  return out;
}

Rigid3d RigidFromCvRt(const cv::Mat& R, const cv::Mat& t_m) {
  cv::Mat R64, t64;
  R.convertTo(R64, CV_64F);
  t_m.convertTo(t64, CV_64F);
  Eigen::Matrix3d rotation;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) rotation(r, c) = R64.at<double>(r, c);
  // OpenCV's solvers return rotations orthonormal to about 1e-9; re-orthonormalise through a quaternion.
  return Rigid3d(Eigen::Quaterniond(rotation).normalized(),
                 Eigen::Vector3d(t64.at<double>(0), t64.at<double>(1), t64.at<double>(2)));
}

std::vector<cv::Point3f> CvObjectPoints(const BoardDetection& detection, const std::vector<Eigen::Vector3d>& points_board) {
  std::vector<cv::Point3f> out;
  out.reserve(detection.corner_ids.size());
  for (int id : detection.corner_ids) {
    MOCAP_CHECK(id >= 0 && static_cast<size_t>(id) < points_board.size(), "corner id ", id, " outside the board");
    const Eigen::Vector3d& p = points_board[static_cast<size_t>(id)];
    out.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  }
  return out;
}

std::vector<cv::Point2f> CvImagePoints(const BoardDetection& detection) {
  std::vector<cv::Point2f> out;
  out.reserve(detection.corners_px.size());
  for (const Eigen::Vector2d& p : detection.corners_px) out.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  return out;
}

}  // namespace mocap
