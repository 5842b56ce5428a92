#pragma once
// Ground-truth motion of a scenario: for any time t (seconds of scenario time) the pose of every object,
// occluder and of the camera. Between keyframes poses follow a minimum-jerk blend
// s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5 (Flash & Hogan 1985): translation linear in s, rotation SLERP in
// s, so the motion is C2 with zero velocity and acceleration at each keyframe. Before the first and
// after the last keyframe the pose holds.
#include <Eigen/Core>
#include <vector>

#include "sim/scenario.h"

namespace mocap::sim {

struct Twist {
  Eigen::Vector3d linear_mps = Eigen::Vector3d::Zero();      ///< velocity of the frame origin, world
  Eigen::Vector3d angular_degps = Eigen::Vector3d::Zero();   ///< angular velocity, world, deg/s
};

/// Minimum-jerk blend factor for tau in [0, 1] (clamped) and its derivative ds/dtau.
double MinimumJerk(double tau);
double MinimumJerkRate(double tau);

/// Pose along keyframes at time t. Precondition: non-empty, times strictly increasing.
Rigid3d EvaluateKeyframes(const std::vector<PoseKeyframe>& keyframes, double t_s);

class SceneMotion {
 public:
  /// Precondition: scenario.check() passed.
  explicit SceneMotion(const Scenario& scenario);

  Rigid3d T_world_mesh(size_t object, double t_s) const;
  Rigid3d T_world_occluder(size_t occluder, double t_s) const;
  Rigid3d T_world_camera(double t_s) const;
  /// Velocities by central differences over 1 ms (the motions are C1).
  Twist ObjectTwist(size_t object, double t_s) const;
  Twist CameraTwist(double t_s) const;

  const Scenario& scenario() const { return scenario_; }

 private:
  Rigid3d Shake(double t_s) const;

  Scenario scenario_;
  std::vector<Eigen::Vector3d> shake_freq_hz_, shake_phase_;  ///< tremor of a hand-held camera
};

/// Finite-difference twist of a pose function.
template <typename PoseAt>
Twist DifferentiatePose(const PoseAt& pose_at, double t_s, double h_s = 1e-3) {
  const Rigid3d before = pose_at(t_s - h_s), after = pose_at(t_s + h_s);
  Twist twist;
  twist.linear_mps = (after.translation() - before.translation()) / (2 * h_s);
  const Eigen::AngleAxisd delta(after.rotation() * before.rotation().inverse());
  twist.angular_degps = delta.axis() * DegFromRad(delta.angle()) / (2 * h_s);
  return twist;
}

}  // namespace mocap::sim
