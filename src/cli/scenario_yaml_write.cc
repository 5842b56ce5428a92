// EncodeScenarioYaml: the YAML form of a scenario, readable by ParseScenarioYaml (round trip tested).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <set>
#include <sstream>

#include "cli/scenario_yaml.h"

namespace mocap::cli {
namespace {

/// Rounds for printing; adding 0.0 turns -0.0 into 0.0.
double Clean(double value, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(value * scale) / scale + 0.0;
}

std::string List(std::initializer_list<double> values, int decimals) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(decimals) << "[";
  bool first = true;
  for (double v : values) {
    out << (first ? "" : ", ") << Clean(v, decimals);
    first = false;
  }
  out << "]";
  return out.str();
}

/// `text` as a YAML scalar that reads back as exactly `text`, in block and flow context alike: plain
/// when it is a simple word (every name the simulator ships), else double-quoted with '"', '\\' and
/// control bytes escaped (a name holding a newline or ": " once made the written file unreadable).
std::string Scalar(const std::string& text) {
  static const std::set<std::string> kWords = {"true", "false", "yes", "no", "on", "off", "y", "n", "null"};
  std::string lower = text;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  const bool word = !text.empty() && (std::isalpha(static_cast<unsigned char>(text[0])) || text[0] == '_') &&
                    std::all_of(text.begin(), text.end(), [](unsigned char c) {
                      return std::isalnum(c) || c == '_' || c == '-' || c == '.' || c == '/';
                    });
  if (word && !kWords.count(lower)) return text;
  std::string quoted = "\"";
  for (const unsigned char c : text) {
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7f) {
      char escape[8];
      std::snprintf(escape, sizeof(escape), "\\x%02x", c);
      quoted += escape;
    } else {
      quoted += static_cast<char>(c);
    }
  }
  return quoted + "\"";
}

std::string Vec(const Eigen::Vector3d& v, int decimals = 6) { return List({v.x(), v.y(), v.z()}, decimals); }

/// roll, pitch, yaw (degrees) with R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Vector3d RpyDeg(const Rigid3d& pose) {
  const Eigen::Matrix3d R = pose.rotation_matrix();
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double roll = std::atan2(R(2, 1), R(2, 2));
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  return {DegFromRad(roll), DegFromRad(pitch), DegFromRad(yaw)};
}

std::string Pose(const Rigid3d& pose) {
  return "{translation_m: " + Vec(pose.translation()) + ", rpy_deg: " + Vec(RpyDeg(pose), 6) + "}";
}

void Keyframes(std::ostringstream& out, const std::vector<sim::PoseKeyframe>& keyframes, const std::string& indent) {
  for (const auto& k : keyframes) {
    const Eigen::Vector3d rpy = RpyDeg(k.pose);
    out << indent << "- {t_s: " << Clean(k.t_s, 6) << ", translation_m: " << Vec(k.pose.translation())
        << ", rpy_deg: " << Vec(rpy, 6) << "}\n";
  }
}

}  // namespace

std::string EncodeScenarioYaml(const sim::Scenario& s) {
  const sim::ScenarioOptions& o = s.options;
  std::ostringstream out;
  out << std::setprecision(10);
  out << "# Simulation scenario (format: docs/simulation.md). Poses: translation in metres, rpy_deg =\n"
         "# roll, pitch, yaw in degrees with R = Rz(yaw) * Ry(pitch) * Rx(roll); world z up, floor at z = 0.\n";
  out << "name: " << Scalar(o.name) << "\nseed: " << o.seed << "\nframe_rate_hz: " << o.frame_rate_hz << "\nframe_count: " << o.frame_count
      << "\nstart_s: " << o.start_s << "\nsensor: " << sim::ToString(o.sensor) << "\n";
  const sim::TrackerOptions& t = o.tracker;
  out << "tracker:\n  rate_hz: " << t.rate_hz << "\n  latency_ms: " << t.latency_ms << "\n  noise_rms_mm: " << t.noise_rms_mm
      << "\n  max_marker_angle_deg: " << t.max_marker_angle_deg << "\n  min_markers: " << t.min_markers
      << "\n  dropout_probability: " << t.dropout_probability << "\n  volume: {near_m: " << t.volume.near_m
      << ", far_m: " << t.volume.far_m << ", half_width_far_m: " << t.volume.half_width_far_m
      << ", half_height_far_m: " << t.volume.half_height_far_m << "}\n  pose: " << Pose(t.T_world_tracker) << "\n";
  const sim::Kinect1Options& k1 = o.kinect1;
  out << "kinect1:\n  noise_coefficient_per_m: " << k1.noise_coefficient_per_m << "\n  quantise: " << (k1.quantise ? "true" : "false")
      << "\n  disparity_a: " << k1.disparity_a << "\n  disparity_b: " << k1.disparity_b << "\n  min_depth_m: " << k1.min_depth_m
      << "\n  max_depth_m: " << k1.max_depth_m << "\n  ir_camera_x_m: " << k1.ir_camera_x_m << "\n  projector_x_m: " << k1.projector_x_m
      << "\n  edge_jump_fraction: " << k1.edge_jump_fraction << "\n  edge_min_jump_m: " << k1.edge_min_jump_m
      << "\n  edge_invalid_probability: " << k1.edge_invalid_probability << "\n  color_noise_sigma: " << k1.color_noise_sigma << "\n";
  const sim::Kinect2Options& k2 = o.kinect2;
  out << "kinect2:\n  min_depth_m: " << k2.min_depth_m << "\n  max_depth_m: " << k2.max_depth_m
      << "\n  tof_noise: " << (k2.tof_noise ? "true" : "false") << "\n  max_incidence_deg: " << k2.max_incidence_deg
      << "\n  edge_jump_m: " << k2.edge_jump_m << "\n  flying_pixel_probability: " << k2.flying_pixel_probability
      << "\n  colour_delay_ms: " << k2.colour_delay_ms << "\n  colour_jitter_ms: " << k2.colour_jitter_ms
      << "\n  color_noise_sigma: " << k2.color_noise_sigma << "\n";
  const sim::CameraMotion& c = s.camera;
  out << "camera:\n  motion: " << (c.type == sim::CameraMotion::Type::kRobotHead ? "robot_head" : "handheld")
      << "\n  head_pose: " << Pose(c.T_world_head) << "\n  T_tilt_camera: " << Pose(c.T_tilt_camera) << "\n";
  if (!c.pan_tilt.empty()) {
    out << "  pan_tilt:\n";
    for (const auto& k : c.pan_tilt) out << "    - {t_s: " << k.t_s << ", pan_deg: " << k.pan_deg << ", tilt_deg: " << k.tilt_deg << "}\n";
  }
  if (!c.handheld.empty()) {
    out << "  keyframes:\n";
    Keyframes(out, c.handheld, "    ");
  }
  out << "  shake_mm: " << c.handheld_shake_mm << "\n  shake_deg: " << c.handheld_shake_deg << "\n  tracker_body:\n    name: "
      << Scalar(s.camera_body.name) << "\n    markers_m:\n";
  for (const auto& m : s.camera_body.markers_m) out << "      - " << Vec(m, 4) << "\n";
  out << "    marker_normal: " << Vec(s.camera_body.normal_body) << "\n  T_cambody_camera: " << Pose(s.T_cambody_camera) << "\n";
  out << "objects:\n";
  for (const auto& obj : s.objects) {
    out << "  - name: " << Scalar(obj.name) << "\n";
    if (obj.depth_loss > 0) out << "    depth_loss: " << obj.depth_loss << "\n";
    out << "    keyframes:\n";
    Keyframes(out, obj.motion, "      ");
  }
  out << "occluders:" << (s.occluders.empty() ? " []" : "") << "\n";
  for (const auto& occ : s.occluders) {
    out << "  - name: " << Scalar(occ.name) << "\n    mesh: " << Scalar(occ.mesh) << "\n    box_center_m: " << Vec(occ.box_center_m)
        << "\n    box_half_extents_m: " << Vec(occ.box_half_extents_m) << "\n";
    if (occ.depth_loss > 0) out << "    depth_loss: " << occ.depth_loss << "\n";
    out << "    keyframes:\n";
    Keyframes(out, occ.motion, "      ");
  }
  const sim::CalibrationErrors& e = o.errors;
  out << "errors:\n  camera_mount: {translation_m: " << Vec(e.camera_mount_translation_m)
      << ", rotation_deg: " << Vec(e.camera_mount_rotation_deg) << "}\n  object_mounts:" << (e.object_mounts.empty() ? " []" : "") << "\n";
  for (const auto& m : e.object_mounts)
    out << "    - {object: " << Scalar(m.object) << ", translation_m: " << Vec(m.translation_m)
        << ", rotation_deg: " << Vec(m.rotation_deg) << "}\n";
  out << "  latency_ms: " << e.latency_ms << "\n  focal_scale: " << e.focal_scale
      << "\n  principal_point_px: " << List({e.principal_point_px.x(), e.principal_point_px.y()}, 3) << "\n";
  return out.str();
}

}  // namespace mocap::cli
