#pragma once
// The accelerated ICP of Besl & McKay ("A Method for Registration of 3-D Shapes", IEEE PAMI 14(2), 1992,
// section IV-C): when successive updates of the registration state point the same way, the state is
// extrapolated along the last update, by the minimum of a parabola fitted to the mean squared error
// along the path (or the zero of a line), at most `max_factor` update lengths. Point-to-point ICP
// creeps along weakly constrained directions (a crop sliding on a box face); the extrapolation covers
// many such steps at once.
//
// The state is [L * rotation vector, position of the source centroid] with L the RMS radius of the
// source about its centroid, so both halves are in metres (Besl & McKay mix a unit quaternion with a
// translation). Internal to AlignPointToPoint.
#include <array>
#include <optional>

#include "core/rigid3.h"
#include "validate/point_cloud.h"

namespace mocap::icp_detail {

class BeslMcKayAccelerator {
 public:
  /// `angle_deg`: the largest angle between successive updates that counts as "the same way"
  /// (Besl & McKay's delta-theta, 10 deg); `max_factor`: the longest extrapolation in update lengths
  /// (their 25).
  BeslMcKayAccelerator(const PointCloud& source, double angle_deg, double max_factor);

  /// Records the pose after an ICP update and the mean squared residual of that update's
  /// correspondences at it (Besl & McKay's d_k). Returns the extrapolated pose when the last three
  /// updates line up; the history then restarts from the returned pose's predecessor.
  std::optional<Rigid3d> Update(const Rigid3d& T_target_source, double mse_m2);

  /// Forgets the history (after the objective changed: another gate or point subset).
  void Reset() { count_ = 0; }

 private:
  /// State difference b - a (metres): [L * log(R_b R_a^T), R_b c + t_b - (R_a c + t_a)].
  Eigen::Matrix<double, 6, 1> Delta(const Rigid3d& a, const Rigid3d& b) const;
  /// How far to extrapolate (metres of state) from the last pose, 0 for not at all.
  double StepLength(double last_length, double previous_length) const;

  Eigen::Vector3d centroid_source_;
  double radius_m_ = 1.0;
  double cos_angle_ = 1.0;
  double max_factor_ = 1.0;
  std::array<Rigid3d, 4> poses_;  ///< oldest first; the last `count_` are valid
  std::array<double, 4> mse_m2_{};
  int count_ = 0;
};

}  // namespace mocap::icp_detail
