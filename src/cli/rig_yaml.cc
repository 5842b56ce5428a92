#include "cli/rig_yaml.h"

#include <cmath>

#include "cli/yaml_util.h"
#include "core/check.h"

namespace mocap::cli {

Rig LoadRigYaml(const std::filesystem::path& path) {
  const YAML::Node root = LoadYamlFile(path);
  Rig rig;
  rig.name = Optional<std::string>(path, root, "name", path.stem().string());
  rig.tracker_latency_ns = std::llround(Optional<double>(path, root, "tracker_latency_ms", 0.0) * 1e6);
  if (const YAML::Node cameras = root["cameras"]) {
    if (!cameras.IsSequence()) throw InputError(Where(path, cameras), "'cameras' must be a list");
    for (const auto& node : cameras) {
      RigCamera c;
      c.camera = Required<std::string>(path, node, "name");
      if (node["intrinsics"]) c.color_camera = Intrinsics(path, node["intrinsics"]);
      if (node["body"]) c.body = Required<std::string>(path, node, "body");
      if (node["T_body_camera"]) c.T_body_camera = Pose(path, node["T_body_camera"]);
      rig.cameras.push_back(c);
    }
  }
  rig.check(path.string());
  return rig;
}

}  // namespace mocap::cli
