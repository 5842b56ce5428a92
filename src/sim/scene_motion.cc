#include "sim/scene_motion.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/check.h"
#include "sim/rng.h"

namespace mocap::sim {

double MinimumJerk(double tau) {
  tau = std::clamp(tau, 0.0, 1.0);
  return tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau);
}

double MinimumJerkRate(double tau) {
  if (tau <= 0 || tau >= 1) return 0;
  return 30.0 * tau * tau * (1.0 - tau) * (1.0 - tau);
}

Rigid3d EvaluateKeyframes(const std::vector<PoseKeyframe>& keyframes, double t_s) {
  MOCAP_CHECK(!keyframes.empty(), "motion without keyframes");
  if (t_s <= keyframes.front().t_s) return keyframes.front().pose;
  if (t_s >= keyframes.back().t_s) return keyframes.back().pose;
  const auto next = std::upper_bound(keyframes.begin(), keyframes.end(), t_s,
                                     [](double t, const PoseKeyframe& k) { return t < k.t_s; });
  const PoseKeyframe& b = *next;
  const PoseKeyframe& a = *(next - 1);
  return Interpolate(a.pose, b.pose, MinimumJerk((t_s - a.t_s) / (b.t_s - a.t_s)));
}

namespace {

double EvaluateAngle(const std::vector<PanTiltKeyframe>& keyframes, double t_s, double PanTiltKeyframe::*angle) {
  if (t_s <= keyframes.front().t_s) return keyframes.front().*angle;
  if (t_s >= keyframes.back().t_s) return keyframes.back().*angle;
  const auto next = std::upper_bound(keyframes.begin(), keyframes.end(), t_s,
                                     [](double t, const PanTiltKeyframe& k) { return t < k.t_s; });
  const PanTiltKeyframe& b = *next;
  const PanTiltKeyframe& a = *(next - 1);
  return a.*angle + (b.*angle - a.*angle) * MinimumJerk((t_s - a.t_s) / (b.t_s - a.t_s));
}

}  // namespace

SceneMotion::SceneMotion(const Scenario& scenario) : scenario_(scenario) {
  Rng rng = Rng::Derive(scenario.options.seed, 0x5ba4e);
  for (int k = 0; k < 3; ++k) {
    shake_freq_hz_.emplace_back(rng.Uniform(0.4, 3.0), rng.Uniform(0.4, 3.0), rng.Uniform(0.4, 3.0));
    shake_phase_.emplace_back(rng.Uniform(0, 2 * std::numbers::pi), rng.Uniform(0, 2 * std::numbers::pi),
                              rng.Uniform(0, 2 * std::numbers::pi));
  }
}

Rigid3d SceneMotion::T_world_mesh(size_t object, double t_s) const {
  MOCAP_CHECK(object < scenario_.objects.size(), "object index out of range");
  return EvaluateKeyframes(scenario_.objects[object].motion, t_s);
}

Rigid3d SceneMotion::T_world_occluder(size_t occluder, double t_s) const {
  MOCAP_CHECK(occluder < scenario_.occluders.size(), "occluder index out of range");
  return EvaluateKeyframes(scenario_.occluders[occluder].motion, t_s);
}

Rigid3d SceneMotion::Shake(double t_s) const {
  // Smooth tremor: three sinusoids per axis; with random phases each has RMS amplitude / sqrt(2), so the
  // amplitudes are scaled to give the requested RMS over the three.
  const CameraMotion& camera = scenario_.camera;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero(), rotation = Eigen::Vector3d::Zero();
  const double scale = std::sqrt(2.0 / 3.0);
  for (int k = 0; k < 3; ++k) {
    for (int axis = 0; axis < 3; ++axis) {
      const double s = std::sin(2 * std::numbers::pi * shake_freq_hz_[k][axis] * t_s + shake_phase_[k][axis]);
      offset[axis] += scale * camera.handheld_shake_mm * 1e-3 / std::sqrt(3.0) * s;
      rotation[(axis + k) % 3] += scale * RadFromDeg(camera.handheld_shake_deg) / std::sqrt(3.0) * s;
    }
  }
  return Rigid3d::FromRvec(rotation, offset);
}

Rigid3d SceneMotion::T_world_camera(double t_s) const {
  const CameraMotion& camera = scenario_.camera;
  if (camera.type == CameraMotion::Type::kHandheld) return EvaluateKeyframes(camera.handheld, t_s) * Shake(t_s);
  const double pan = RadFromDeg(EvaluateAngle(camera.pan_tilt, t_s, &PanTiltKeyframe::pan_deg));
  const double tilt = RadFromDeg(EvaluateAngle(camera.pan_tilt, t_s, &PanTiltKeyframe::tilt_deg));
  const Rigid3d pan_tilt(Eigen::Quaterniond(Eigen::AngleAxisd(pan, Eigen::Vector3d::UnitZ()) *
                                            Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitY())),
                         Eigen::Vector3d::Zero());
  return camera.T_world_head * pan_tilt * camera.T_tilt_camera;
}

Twist SceneMotion::ObjectTwist(size_t object, double t_s) const {
  return DifferentiatePose([&](double t) { return T_world_mesh(object, t); }, t_s);
}

Twist SceneMotion::CameraTwist(double t_s) const {
  return DifferentiatePose([&](double t) { return T_world_camera(t); }, t_s);
}

}  // namespace mocap::sim
