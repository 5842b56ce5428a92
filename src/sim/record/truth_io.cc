#include "sim/record/truth_io.h"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/check.h"
#include "session/manifest.h"

namespace mocap::sim {
namespace {

nlohmann::json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

std::string Num(double x) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.12g", x);
  return buffer;
}

std::string YamlPose(const Rigid3d& T, const std::string& indent) {
  const Eigen::Vector3d t = T.translation();
  const Eigen::Vector4d q = T.quat_wxyz();
  return indent + "translation_m: [" + Num(t.x()) + ", " + Num(t.y()) + ", " + Num(t.z()) + "]\n" + indent +
         "rotation_wxyz: [" + Num(q[0]) + ", " + Num(q[1]) + ", " + Num(q[2]) + ", " + Num(q[3]) + "]\n";
}

}  // namespace

nlohmann::json ToJson(const RigCalibration& c) {
  nlohmann::json mounts = nlohmann::json::object();
  for (size_t i = 0; i < c.objects.size(); ++i) mounts[c.objects[i]] = mocap::ToJson(c.T_objbody_mesh[i]);
  return {{"T_cambody_camera", mocap::ToJson(c.T_cambody_camera)},
          {"T_objbody_mesh", mounts},
          {"tracker_latency_ns", c.tracker_latency_ns},
          {"color_camera", mocap::ToJson(c.color_camera)},
          {"depth_camera", mocap::ToJson(c.depth_camera)},
          {"T_color_depth", mocap::ToJson(c.T_color_depth)}};
}

nlohmann::json ToJson(const CalibrationErrors& e) {
  nlohmann::json mounts = nlohmann::json::array();
  for (const auto& m : e.object_mounts)
    mounts.push_back({{"object", m.object}, {"translation_m", Vec(m.translation_m)}, {"rotation_deg", Vec(m.rotation_deg)}});
  return {{"camera_mount", {{"translation_m", Vec(e.camera_mount_translation_m)}, {"rotation_deg", Vec(e.camera_mount_rotation_deg)}}},
          {"object_mounts", mounts},
          {"latency_ms", e.latency_ms},
          {"focal_scale", e.focal_scale},
          {"principal_point_px", {e.principal_point_px.x(), e.principal_point_px.y()}}};
}

nlohmann::json FrameTruthJson(const FrameTruth& f) {
  nlohmann::json objects = nlohmann::json::array(), occluders = nlohmann::json::array();
  for (const ObjectTruth& o : f.objects)
    objects.push_back({{"name", o.name},
                       {"id", o.id},
                       {"T_camera_mesh", mocap::ToJson(o.T_camera_mesh)},
                       {"T_color_mesh", mocap::ToJson(o.T_color_mesh)},
                       {"speed_mps", o.speed_mps},
                       {"angular_speed_degps", o.angular_speed_degps}});
  for (const OccluderTruth& o : f.occluders)
    occluders.push_back({{"name", o.name}, {"T_camera_occluder", mocap::ToJson(o.T_camera_occluder)}});
  return {{"index", f.index},
          {"depth_time_ns", f.depth_time_ns},
          {"color_time_ns", f.color_time_ns},
          {"T_world_camera", mocap::ToJson(f.T_world_camera)},
          {"T_world_color", mocap::ToJson(f.T_world_color)},
          {"objects", objects},
          {"occluders", occluders}};
}

std::string EncodeRigYaml(const std::string& name, const std::string& camera, const std::string& camera_body,
                          const RigCalibration& c) {
  const PinholeCamera& k = c.color_camera;
  std::ostringstream out;
  out << "# Calibration handed to the labeller by `mocaplabel sim record` (schema: docs/rig.md); the\n"
         "# scenario's injected errors are applied here, the truth is in truth/calibration.json.\n"
      << "name: " << name << "\ntracker_latency_ms: " << Num(c.tracker_latency_ns * 1e-6) << "\ncameras:\n"
      << "  - name: " << camera << "\n    body: " << camera_body << "\n    T_body_camera:\n"
      << YamlPose(c.T_cambody_camera, "      ") << "    intrinsics:\n      width: " << k.width
      << "\n      height: " << k.height << "\n      fx: " << Num(k.fx) << "\n      fy: " << Num(k.fy)
      << "\n      cx: " << Num(k.cx) << "\n      cy: " << Num(k.cy) << "\n      dist: [";
  for (size_t i = 0; i < k.dist.size(); ++i) out << (i ? ", " : "") << Num(k.dist[i]);
  out << "]\n";
  return out.str();
}

ObjectLibrary LibraryForLabelling(const ObjectLibrary& library, const RigCalibration& calibration,
                                  const std::filesystem::path& library_dir, const std::filesystem::path& yaml_dir) {
  namespace fs = std::filesystem;
  ObjectLibrary out = library;
  for (ObjectSpec& spec : out.objects) {
    spec.mesh = fs::relative(fs::absolute(library_dir / spec.mesh), fs::absolute(yaml_dir)).generic_string();
    for (size_t i = 0; i < calibration.objects.size(); ++i)
      if (calibration.objects[i] == spec.name) spec.T_body_mesh = calibration.T_objbody_mesh[i];
  }
  return out;
}

void WriteJsonFile(const std::filesystem::path& path, const nlohmann::json& json) {
  std::ofstream out(path);
  out << json.dump(2) << '\n';
  out.close();
  if (!out) throw InputError(path.string(), "could not write (disk full or not writable?)");
}

}  // namespace mocap::sim
