#include "sim/scenario.h"

#include <cmath>
#include <set>

#include "core/check.h"

namespace mocap::sim {
namespace {

void CheckKeyframeTimes(const std::vector<double>& times, const std::string& where) {
  if (times.empty()) throw InputError(where, "needs at least one keyframe");
  for (size_t i = 0; i < times.size(); ++i) {
    if (!std::isfinite(times[i])) throw InputError(Str(where, "[", i, "]"), "time is not a finite number");
    if (i > 0 && !(times[i] > times[i - 1]))
      throw InputError(Str(where, "[", i, "]"), Str("keyframe times must increase (", times[i - 1], " s then ", times[i], " s)"));
  }
}

std::vector<double> TimesOf(const std::vector<PoseKeyframe>& keyframes) {
  std::vector<double> times;
  for (const PoseKeyframe& k : keyframes) times.push_back(k.t_s);
  return times;
}

}  // namespace

bool CalibrationErrors::any() const {
  return !camera_mount_translation_m.isZero() || !camera_mount_rotation_deg.isZero() || !object_mounts.empty() ||
         latency_ms != 0 || focal_scale != 0 || !principal_point_px.isZero();
}

std::string_view ToString(SensorKind kind) { return kind == SensorKind::kKinect1 ? "kinect1" : "kinect2"; }

SensorKind SensorKindFromString(std::string_view name, const std::string& where) {
  if (name == "kinect1") return SensorKind::kKinect1;
  if (name == "kinect2") return SensorKind::kKinect2;
  throw InputError(where, Str("unknown sensor '", name, "' (expected kinect1 or kinect2)"));
}

void ScenarioOptions::check() const {
  if (!(frame_rate_hz > 0 && frame_rate_hz <= 200)) throw InputError("frame_rate_hz", Str("must be in (0, 200], got ", frame_rate_hz));
  if (frame_count < 1 || frame_count > 100000) throw InputError("frame_count", Str("must be in [1, 100000], got ", frame_count));
  if (!std::isfinite(start_s)) throw InputError("start_s", "must be a finite number");
  tracker.check();
  kinect1.check();
  kinect2.check();
  if (errors.camera_mount_translation_m.norm() > 0.5 || errors.camera_mount_rotation_deg.norm() > 45)
    throw InputError("errors.camera_mount", "implausibly large (> 0.5 m or > 45 deg)");
  if (std::abs(errors.latency_ms) > 1000) throw InputError("errors.latency_ms", "must be within +-1000 ms");
  if (std::abs(errors.focal_scale) > 0.5) throw InputError("errors.focal_scale", "must be within +-0.5");
  for (const auto& mount : errors.object_mounts)
    if (mount.translation_m.norm() > 0.5 || mount.rotation_deg.norm() > 45)
      throw InputError(Str("errors.object_mounts[", mount.object, "]"), "implausibly large (> 0.5 m or > 45 deg)");
}

void Scenario::check(const SimObjects& library, const std::string& where) const {
  options.check();
  if (objects.empty()) throw InputError(where, "scenario without objects");
  std::set<std::string> names;
  for (size_t i = 0; i < objects.size(); ++i) {
    const std::string at = Str(where, ": objects[", i, "]");
    if (library.Find(objects[i].name) == nullptr) throw InputError(at, Str("object '", objects[i].name, "' is not in the object library"));
    if (!names.insert(objects[i].name).second) throw InputError(at, Str("object '", objects[i].name, "' appears twice"));
    CheckKeyframeTimes(TimesOf(objects[i].motion), at + ".motion");
    if (!(objects[i].depth_loss >= 0 && objects[i].depth_loss <= 1)) throw InputError(at, "depth_loss must be in [0, 1]");
  }
  for (size_t i = 0; i < occluders.size(); ++i) {
    const std::string at = Str(where, ": occluders[", i, "]");
    if (occluders[i].mesh.empty()) throw InputError(at, "occluder without a mesh");
    if (!(occluders[i].box_half_extents_m.array() > 0).all()) throw InputError(at, "box_half_extents_m must be positive");
    CheckKeyframeTimes(TimesOf(occluders[i].motion), at + ".motion");
    if (!(occluders[i].depth_loss >= 0 && occluders[i].depth_loss <= 1)) throw InputError(at, "depth_loss must be in [0, 1]");
  }
  if (camera.type == CameraMotion::Type::kRobotHead) {
    std::vector<double> times;
    for (const PanTiltKeyframe& k : camera.pan_tilt) times.push_back(k.t_s);
    CheckKeyframeTimes(times, where + ": camera.pan_tilt");
  } else {
    CheckKeyframeTimes(TimesOf(camera.handheld), where + ": camera.keyframes");
  }
  if (camera.handheld_shake_mm < 0 || camera.handheld_shake_deg < 0) throw InputError(where + ": camera", "shake must be >= 0");
  camera_body.check(where + ": camera.tracker_body");
  for (const auto& mount : options.errors.object_mounts)
    if (names.count(mount.object) == 0)
      throw InputError(where + ": errors.object_mounts", Str("object '", mount.object, "' is not in the scenario"));
}

Rigid3d LookAt(const Eigen::Vector3d& position, const Eigen::Vector3d& target, const Eigen::Vector3d& up, bool forward_is_minus_z) {
  const Eigen::Vector3d forward = (target - position).normalized();
  MOCAP_CHECK(forward.cross(up).norm() > 1e-6, "look-at direction parallel to up");
  const Eigen::Vector3d x = forward.cross(up).normalized();
  const Eigen::Vector3d z = forward_is_minus_z ? Eigen::Vector3d(-forward) : forward;
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R << x, y, z;
  return Rigid3d(R, position);
}

Rigid3d PoseXyzRpy(const Eigen::Vector3d& xyz_m, const Eigen::Vector3d& rpy_deg) {
  const Eigen::Quaterniond q = Eigen::AngleAxisd(RadFromDeg(rpy_deg.z()), Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(RadFromDeg(rpy_deg.y()), Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(RadFromDeg(rpy_deg.x()), Eigen::Vector3d::UnitX());
  return Rigid3d(q, xyz_m);
}

}  // namespace mocap::sim
