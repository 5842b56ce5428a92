#pragma once
// Conversions between the project's types (PinholeCamera, Rigid3d, Eigen points) and the cv:: types
// the calibration calls of OpenCV take. Internal to src/calibrate.
#include <opencv2/core.hpp>

#include <Eigen/Core>
#include <vector>

#include "calibrate/board.h"
#include "core/camera.h"
#include "core/rigid3.h"

namespace mocap {

/// 3x3 CV_64F camera matrix K.
cv::Mat CvCameraMatrix(const PinholeCamera& camera);
/// 1x8 CV_64F distortion coefficients, OpenCV order k1 k2 p1 p2 k3 k4 k5 k6.
cv::Mat CvDistCoeffs(const PinholeCamera& camera);
/// The camera from OpenCV's K and 4, 5 or 8 distortion coefficients (further ones must be zero).
PinholeCamera CameraFromCv(const cv::Mat& K, const cv::Mat& dist, cv::Size image_size);

/// T_camera_object from a cv::solvePnP-style (rvec, tvec): p_camera = R(rvec) p_object + tvec.
Rigid3d RigidFromCv(const cv::Vec3d& rvec, const cv::Vec3d& tvec_m);
void CvFromRigid(const Rigid3d& T, cv::Vec3d& rvec, cv::Vec3d& tvec_m);
cv::Matx33d CvRotation(const Rigid3d& T);
Rigid3d RigidFromCvRt(const cv::Mat& R, const cv::Mat& t_m);

/// The detected corners' board points (metres) and image points (pixels), in detection order.
std::vector<cv::Point3f> CvObjectPoints(const BoardDetection& detection, const std::vector<Eigen::Vector3d>& points_board);
std::vector<cv::Point2f> CvImagePoints(const BoardDetection& detection);

}  // namespace mocap
