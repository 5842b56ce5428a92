#include "sim/record/truth_io.h"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/check.h"
#include "session/manifest.h"
#include "session/records.h"

namespace mocap::sim {
namespace {

nlohmann::json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

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

std::filesystem::path TruthInstancePng(const std::filesystem::path& truth_dir, int64_t frame) {
  return truth_dir / "instance" / (FrameFileStem(frame) + ".png");
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

void WriteJsonFile(const std::filesystem::path& path, const nlohmann::json& json) {
  std::ofstream out(path);
  out << json.dump(2) << '\n';
  out.close();
  if (!out) throw InputError(path.string(), "could not write (disk full or not writable?)");
}

}  // namespace mocap::sim
