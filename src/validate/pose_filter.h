#pragma once
// Kalman filter on an object's 6-DoF pose and velocity in the world (tracker) frame: the tracking phase
// of the paper ("The pose obtained by registration is used as a measurement update in a Kalman filter
// to track each object's 6-DoF pose and velocities. By fusing known camera motions ... the filter is
// able to handle temporary object occlusions and outlier pose estimates").
//
// The state lives in the world frame, so the camera motion (T_world_camera from the camera's tracker
// body) is fused exactly: a static object stays put in the world however the camera moves, and the
// prediction in the camera is T_camera_world(t) * T_world_object(t).
//
// Error-state EKF on SO(3) x R^9 (performance.md section 5): nominal state R (world from object),
// p (object origin in world, m), w (angular velocity, world, rad/s), v (velocity, world, m/s); error
// state [dtheta, dp, dw, dv] with R = Exp(dtheta) * R_hat. Constant velocity with white acceleration.
#include <Eigen/Core>
#include <cstdint>

#include "core/rigid3.h"

namespace mocap {

struct PoseFilterOptions {
  double accel_sigma_mps2 = 0.5;           ///< white linear acceleration (process noise)
  double angular_accel_sigma_radps2 = 2.0; ///< white angular acceleration
  double position_sigma_m = 0.002;         ///< ICP position noise at a(M, S) = 1
  double rotation_sigma_deg = 1.0;         ///< ICP rotation noise at a(M, S) = 1
  /// The score informs the measurement noise: sigma(a) = sigma / a^k (k = this), so a fit that explains
  /// fewer model points counts for less.
  double score_noise_exponent = 2.0;
  /// Measurements whose squared Mahalanobis distance exceeds this are rejected as outliers
  /// (chi-square, 6 degrees of freedom, 99.9 %).
  double gate_chi2 = 22.46;
  double initial_velocity_sigma_mps = 0.5;
  double initial_angular_velocity_sigma_radps = 1.0;
  /// The track is lost when the position standard deviation grows beyond this ("propagates ... until a
  /// maximum pose uncertainty").
  double max_position_sigma_m = 0.05;
  void check() const;
};

struct FilterUpdate {
  bool accepted = false;
  double mahalanobis_sq = 0.0;
};

class PoseFilter {
 public:
  using Matrix12d = Eigen::Matrix<double, 12, 12>;

  explicit PoseFilter(const PoseFilterOptions& options = {});

  bool initialized() const { return initialized_; }
  /// Starts the filter at a measured pose with zero velocity (its uncertainty from the options).
  void Initialize(const Rigid3d& T_world_object, int64_t stamp_ns, double score);
  /// Constant-velocity propagation to `stamp_ns` (no-op for stamps not after the current one).
  void Predict(int64_t stamp_ns);
  /// Measurement update with an ICP pose and its alignment score in (0, 1].
  FilterUpdate Update(const Rigid3d& T_world_object_measured, double score);

  Rigid3d pose() const { return Rigid3d(rotation_, position_); }
  const Eigen::Vector3d& velocity_mps() const { return velocity_; }
  const Eigen::Vector3d& angular_velocity_radps() const { return angular_velocity_; }
  const Matrix12d& covariance() const { return P_; }
  /// sqrt of the largest position variance, metres.
  double position_sigma_m() const;
  bool lost() const { return initialized_ && position_sigma_m() > options_.max_position_sigma_m; }
  int64_t stamp_ns() const { return stamp_ns_; }

 private:
  PoseFilterOptions options_;
  bool initialized_ = false;
  int64_t stamp_ns_ = 0;
  Eigen::Quaterniond rotation_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d position_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();
  Matrix12d P_ = Matrix12d::Identity();
};

/// SO(3) exponential and logarithm (rotation vectors in radians).
Eigen::Quaterniond ExpSO3(const Eigen::Vector3d& rotation_vector);
Eigen::Vector3d LogSO3(const Eigen::Quaterniond& q);

}  // namespace mocap
