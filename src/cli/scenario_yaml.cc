#include "cli/scenario_yaml.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>

#include "core/check.h"
#include "pipeline/yaml_read.h"

namespace mocap::cli {
namespace {

using sim::PoseKeyframe;

using pipeline::As;
using pipeline::Numbers;
using pipeline::YamlDoc;
using pipeline::YamlMap;
using Ctx = YamlDoc;

/// Every key of the map `node` must be one of `allowed` (a typo is an error, with "did you mean").
void CheckKeys(const Ctx& ctx, const YAML::Node& node, std::initializer_list<const char*> allowed) {
  const YamlMap map(ctx, node, "this map", allowed);
}

template <typename T>
void Read(const Ctx& ctx, const YAML::Node& parent, const char* key, T& value) {
  if (const YAML::Node node = parent[key]) value = As<T>(ctx, node, key);
}

Eigen::Vector3d Vec3(const Ctx& ctx, const YAML::Node& node, const std::string& what) { return pipeline::Vector3(ctx, node, what); }

void ReadVec3(const Ctx& ctx, const YAML::Node& parent, const char* key, Eigen::Vector3d& value) {
  if (const YAML::Node node = parent[key]) value = Vec3(ctx, node, key);
}

/// {translation_m, rotation_wxyz | rvec_rad | rpy_deg} or {look_at: {position, target, up}}.
Rigid3d Pose(const Ctx& ctx, const YAML::Node& node, std::initializer_list<const char*> extra_keys = {}, bool minus_z = false) {
  std::vector<const char*> keys{"translation_m", "rotation_wxyz", "rvec_rad", "rpy_deg", "look_at"};
  keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
  if (!node.IsMap()) throw InputError(ctx.Where(node), "expected a pose {translation_m, rotation_wxyz | rvec_rad | rpy_deg} or {look_at}");
  for (const auto& item : node) {
    const std::string key = item.first.as<std::string>();
    if (std::find_if(keys.begin(), keys.end(), [&](const char* k) { return key == k; }) == keys.end())
      throw InputError(ctx.Where(item.first), Str("unknown pose key '", key, "'",
                                                   pipeline::NearestKey(key, {keys.begin(), keys.end()}).empty()
                                                       ? ""
                                                       : Str(" (did you mean '", pipeline::NearestKey(key, {keys.begin(), keys.end()}), "'?)")));
  }
  if (const YAML::Node look = node["look_at"]) {
    CheckKeys(ctx, look, {"position", "target", "up"});
    if (!look["position"] || !look["target"]) throw InputError(ctx.Where(look), "look_at needs 'position' and 'target'");
    const Eigen::Vector3d up = look["up"] ? Vec3(ctx, look["up"], "up") : Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d p = Vec3(ctx, look["position"], "position"), t = Vec3(ctx, look["target"], "target");
    if ((t - p).norm() < 1e-6 || (t - p).normalized().cross(up.normalized()).norm() < 1e-6)
      throw InputError(ctx.Where(look), "look_at: target equals position or the view is parallel to 'up'");
    return sim::LookAt(p, t, up.normalized(), minus_z);
  }
  if (!node["translation_m"]) throw InputError(ctx.Where(node), "pose without 'translation_m'");
  const Eigen::Vector3d t = Vec3(ctx, node["translation_m"], "translation_m");
  const int rotations = !!node["rotation_wxyz"] + !!node["rvec_rad"] + !!node["rpy_deg"];
  if (rotations > 1) throw InputError(ctx.Where(node), "give one of rotation_wxyz, rvec_rad, rpy_deg");
  if (node["rvec_rad"]) return Rigid3d::FromRvec(Vec3(ctx, node["rvec_rad"], "rvec_rad"), t);
  if (node["rpy_deg"]) return sim::PoseXyzRpy(t, Vec3(ctx, node["rpy_deg"], "rpy_deg"));
  if (!node["rotation_wxyz"]) return Rigid3d(Eigen::Quaterniond::Identity(), t);
  const auto q = Numbers(ctx, node["rotation_wxyz"], 4, "rotation_wxyz");
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (std::abs(norm - 1.0) > 1e-3)
    throw InputError(ctx.Where(node["rotation_wxyz"]), Str("quaternion norm ", norm, " is not 1 (order is w x y z)"));
  return Rigid3d::FromQuatWxyz(q[0], q[1], q[2], q[3], t);
}

std::vector<PoseKeyframe> Keyframes(const Ctx& ctx, const YAML::Node& node, const std::string& what) {
  if (!node.IsSequence() || node.size() == 0) throw InputError(ctx.Where(node), Str("'", what, "' must be a non-empty list of keyframes"));
  std::vector<PoseKeyframe> keyframes;
  for (const auto& item : node) {
    if (!item["t_s"]) throw InputError(ctx.Where(item), "keyframe without 't_s'");
    keyframes.push_back({As<double>(ctx, item["t_s"], "t_s"), Pose(ctx, item, {"t_s"})});
    if (keyframes.size() > 1 && !(keyframes.back().t_s > keyframes[keyframes.size() - 2].t_s))
      throw InputError(ctx.Where(item), "keyframe times must increase");
  }
  return keyframes;
}

sim::MarkerBody Body(const Ctx& ctx, const YAML::Node& node, sim::MarkerBody body) {
  CheckKeys(ctx, node, {"name", "markers_m", "marker_normal"});
  Read(ctx, node, "name", body.name);
  if (const YAML::Node markers = node["markers_m"]) {
    if (!markers.IsSequence()) throw InputError(ctx.Where(markers), "'markers_m' must be a list of [x, y, z]");
    body.markers_m.clear();
    for (const auto& m : markers) body.markers_m.push_back(Vec3(ctx, m, "markers_m"));
  }
  if (const YAML::Node n = node["marker_normal"]) {
    const Eigen::Vector3d normal = Vec3(ctx, n, "marker_normal");
    if (normal.norm() < 1e-9) throw InputError(ctx.Where(n), "'marker_normal' is zero");
    body.normal_body = normal.normalized();
  }
  body.check(ctx.Where(node));
  return body;
}

void ReadTracker(const Ctx& ctx, const YAML::Node& node, sim::TrackerOptions& t) {
  CheckKeys(ctx, node, {"rate_hz", "latency_ms", "noise_rms_mm", "max_marker_angle_deg", "min_markers", "dropout_probability",
                        "volume", "pose"});
  Read(ctx, node, "rate_hz", t.rate_hz);
  Read(ctx, node, "latency_ms", t.latency_ms);
  Read(ctx, node, "noise_rms_mm", t.noise_rms_mm);
  Read(ctx, node, "max_marker_angle_deg", t.max_marker_angle_deg);
  Read(ctx, node, "min_markers", t.min_markers);
  Read(ctx, node, "dropout_probability", t.dropout_probability);
  if (const YAML::Node v = node["volume"]) {
    CheckKeys(ctx, v, {"near_m", "far_m", "half_width_far_m", "half_height_far_m"});
    Read(ctx, v, "near_m", t.volume.near_m);
    Read(ctx, v, "far_m", t.volume.far_m);
    Read(ctx, v, "half_width_far_m", t.volume.half_width_far_m);
    Read(ctx, v, "half_height_far_m", t.volume.half_height_far_m);
  }
  if (const YAML::Node p = node["pose"]) t.T_world_tracker = Pose(ctx, p, {}, true);
}

void ReadKinect1(const Ctx& ctx, const YAML::Node& node, sim::Kinect1Options& k) {
  CheckKeys(ctx, node, {"noise_coefficient_per_m", "quantise", "disparity_a", "disparity_b", "min_depth_m", "max_depth_m",
                        "ir_camera_x_m", "projector_x_m", "edge_jump_fraction", "edge_min_jump_m", "edge_invalid_probability",
                        "color_noise_sigma"});
  Read(ctx, node, "noise_coefficient_per_m", k.noise_coefficient_per_m);
  Read(ctx, node, "quantise", k.quantise);
  Read(ctx, node, "disparity_a", k.disparity_a);
  Read(ctx, node, "disparity_b", k.disparity_b);
  Read(ctx, node, "min_depth_m", k.min_depth_m);
  Read(ctx, node, "max_depth_m", k.max_depth_m);
  Read(ctx, node, "ir_camera_x_m", k.ir_camera_x_m);
  Read(ctx, node, "projector_x_m", k.projector_x_m);
  Read(ctx, node, "edge_jump_fraction", k.edge_jump_fraction);
  Read(ctx, node, "edge_min_jump_m", k.edge_min_jump_m);
  Read(ctx, node, "edge_invalid_probability", k.edge_invalid_probability);
  Read(ctx, node, "color_noise_sigma", k.color_noise_sigma);
}

void ReadKinect2(const Ctx& ctx, const YAML::Node& node, sim::Kinect2Options& k) {
  CheckKeys(ctx, node, {"min_depth_m", "max_depth_m", "tof_noise", "max_incidence_deg", "edge_jump_m", "flying_pixel_probability",
                        "colour_delay_ms", "colour_jitter_ms", "color_noise_sigma"});
  Read(ctx, node, "min_depth_m", k.min_depth_m);
  Read(ctx, node, "max_depth_m", k.max_depth_m);
  Read(ctx, node, "tof_noise", k.tof_noise);
  Read(ctx, node, "max_incidence_deg", k.max_incidence_deg);
  Read(ctx, node, "edge_jump_m", k.edge_jump_m);
  Read(ctx, node, "flying_pixel_probability", k.flying_pixel_probability);
  Read(ctx, node, "colour_delay_ms", k.colour_delay_ms);
  Read(ctx, node, "colour_jitter_ms", k.colour_jitter_ms);
  Read(ctx, node, "color_noise_sigma", k.color_noise_sigma);
}

void ReadErrors(const Ctx& ctx, const YAML::Node& node, sim::CalibrationErrors& e) {
  CheckKeys(ctx, node, {"camera_mount", "object_mounts", "latency_ms", "focal_scale", "principal_point_px"});
  if (const YAML::Node m = node["camera_mount"]) {
    CheckKeys(ctx, m, {"translation_m", "rotation_deg"});
    ReadVec3(ctx, m, "translation_m", e.camera_mount_translation_m);
    ReadVec3(ctx, m, "rotation_deg", e.camera_mount_rotation_deg);
  }
  if (const YAML::Node list = node["object_mounts"]) {
    if (!list.IsSequence()) throw InputError(ctx.Where(list), "'object_mounts' must be a list");
    for (const auto& m : list) {
      CheckKeys(ctx, m, {"object", "translation_m", "rotation_deg"});
      if (!m["object"]) throw InputError(ctx.Where(m), "object mount error without 'object'");
      sim::CalibrationErrors::ObjectMount mount;
      mount.object = As<std::string>(ctx, m["object"], "object");
      ReadVec3(ctx, m, "translation_m", mount.translation_m);
      ReadVec3(ctx, m, "rotation_deg", mount.rotation_deg);
      e.object_mounts.push_back(mount);
    }
  }
  Read(ctx, node, "latency_ms", e.latency_ms);
  Read(ctx, node, "focal_scale", e.focal_scale);
  if (const YAML::Node pp = node["principal_point_px"]) {
    const auto v = Numbers(ctx, pp, 2, "principal_point_px");
    e.principal_point_px = {v[0], v[1]};
  }
}

void ReadCamera(const Ctx& ctx, const YAML::Node& node, sim::Scenario& s) {
  CheckKeys(ctx, node, {"motion", "head_pose", "T_tilt_camera", "pan_tilt", "keyframes", "shake_mm", "shake_deg", "tracker_body",
                        "T_cambody_camera"});
  sim::CameraMotion& c = s.camera;
  if (const YAML::Node m = node["motion"]) {
    const std::string type = As<std::string>(ctx, m, "motion");
    if (type == "robot_head") {
      c.type = sim::CameraMotion::Type::kRobotHead;
    } else if (type == "handheld") {
      c.type = sim::CameraMotion::Type::kHandheld;
    } else {
      throw InputError(ctx.Where(m), Str("unknown camera motion '", type, "' (expected robot_head or handheld)"));
    }
  }
  if (const YAML::Node p = node["head_pose"]) c.T_world_head = Pose(ctx, p);
  if (const YAML::Node p = node["T_tilt_camera"]) c.T_tilt_camera = Pose(ctx, p);
  if (const YAML::Node list = node["pan_tilt"]) {
    if (!list.IsSequence() || list.size() == 0) throw InputError(ctx.Where(list), "'pan_tilt' must be a non-empty list");
    c.pan_tilt.clear();
    for (const auto& k : list) {
      CheckKeys(ctx, k, {"t_s", "pan_deg", "tilt_deg"});
      if (!k["t_s"]) throw InputError(ctx.Where(k), "pan_tilt keyframe without 't_s'");
      sim::PanTiltKeyframe key;
      Read(ctx, k, "t_s", key.t_s);
      Read(ctx, k, "pan_deg", key.pan_deg);
      Read(ctx, k, "tilt_deg", key.tilt_deg);
      c.pan_tilt.push_back(key);
    }
  }
  if (const YAML::Node k = node["keyframes"]) c.handheld = Keyframes(ctx, k, "keyframes");
  Read(ctx, node, "shake_mm", c.handheld_shake_mm);
  Read(ctx, node, "shake_deg", c.handheld_shake_deg);
  if (const YAML::Node b = node["tracker_body"]) s.camera_body = Body(ctx, b, s.camera_body);
  if (const YAML::Node p = node["T_cambody_camera"]) s.T_cambody_camera = Pose(ctx, p);
}

/// `depth_loss`, the fraction of a surface without depth (sim/depth_loss.h), in [0, 1].
void ReadDepthLoss(const Ctx& ctx, const YAML::Node& parent, double& value) {
  Read(ctx, parent, "depth_loss", value);
  if (!(value >= 0 && value <= 1)) throw InputError(ctx.Where(parent["depth_loss"]), "depth_loss must be in [0, 1]");
}

void ReadScene(const Ctx& ctx, const YAML::Node& root, sim::Scenario& s) {
  if (const YAML::Node list = root["objects"]) {
    if (!list.IsSequence() || list.size() == 0) throw InputError(ctx.Where(list), "'objects' must be a non-empty list");
    s.objects.clear();
    for (const auto& o : list) {
      CheckKeys(ctx, o, {"name", "keyframes", "depth_loss"});
      if (!o["name"] || !o["keyframes"]) throw InputError(ctx.Where(o), "an object needs 'name' and 'keyframes'");
      sim::ScenarioObject object{As<std::string>(ctx, o["name"], "name"), Keyframes(ctx, o["keyframes"], "keyframes")};
      ReadDepthLoss(ctx, o, object.depth_loss);
      s.objects.push_back(object);
    }
  }
  if (const YAML::Node list = root["occluders"]) {
    if (!list.IsSequence()) throw InputError(ctx.Where(list), "'occluders' must be a list");
    s.occluders.clear();
    for (const auto& o : list) {
      CheckKeys(ctx, o, {"name", "mesh", "box_center_m", "box_half_extents_m", "keyframes", "depth_loss"});
      if (!o["name"] || !o["mesh"] || !o["keyframes"]) throw InputError(ctx.Where(o), "an occluder needs 'name', 'mesh' and 'keyframes'");
      sim::ScenarioOccluder occluder;
      occluder.name = As<std::string>(ctx, o["name"], "name");
      occluder.mesh = As<std::string>(ctx, o["mesh"], "mesh");
      ReadVec3(ctx, o, "box_center_m", occluder.box_center_m);
      ReadVec3(ctx, o, "box_half_extents_m", occluder.box_half_extents_m);
      occluder.motion = Keyframes(ctx, o["keyframes"], "keyframes");
      ReadDepthLoss(ctx, o, occluder.depth_loss);
      s.occluders.push_back(occluder);
    }
  }
}

sim::Scenario ScenarioFromDoc(const Ctx& ctx) {
  const std::string& file_name = ctx.file;
  const YAML::Node& root = ctx.root;
  if (!root.IsMap()) throw InputError(file_name, "a scenario must be a YAML map");
  CheckKeys(ctx, root, {"name", "seed", "frame_rate_hz", "frame_count", "start_s", "sensor", "kinect1", "kinect2", "tracker",
                        "camera", "objects", "occluders", "errors"});
  sim::Scenario s = sim::DefaultScenario();
  sim::ScenarioOptions& o = s.options;
  Read(ctx, root, "name", o.name);
  Read(ctx, root, "seed", o.seed);
  Read(ctx, root, "frame_rate_hz", o.frame_rate_hz);
  Read(ctx, root, "frame_count", o.frame_count);
  Read(ctx, root, "start_s", o.start_s);
  if (const YAML::Node sensor = root["sensor"]) o.sensor = sim::SensorKindFromString(As<std::string>(ctx, sensor, "sensor"), ctx.Where(sensor));
  if (const YAML::Node n = root["kinect1"]) ReadKinect1(ctx, n, o.kinect1);
  if (const YAML::Node n = root["kinect2"]) ReadKinect2(ctx, n, o.kinect2);
  if (const YAML::Node n = root["tracker"]) ReadTracker(ctx, n, o.tracker);
  if (const YAML::Node n = root["errors"]) ReadErrors(ctx, n, o.errors);
  if (const YAML::Node n = root["camera"]) ReadCamera(ctx, n, s);
  ReadScene(ctx, root, s);
  try {
    o.check();
  } catch (const InputError& e) {
    throw InputError(file_name, e.what());
  }
  return s;
}

}  // namespace

sim::Scenario ParseScenarioYaml(const std::string& text, const std::string& file_name) {
  return ScenarioFromDoc(pipeline::ParseYaml(text, file_name));
}

sim::Scenario LoadScenarioYaml(const std::filesystem::path& path) { return ScenarioFromDoc(pipeline::LoadYaml(path)); }

}  // namespace mocap::cli
