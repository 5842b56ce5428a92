#include "cli/objects_yaml.h"

#include "cli/yaml_util.h"
#include "core/check.h"

namespace mocap::cli {
namespace {

LabelObject ParseObject(const std::filesystem::path& file, const YAML::Node& node) {
  LabelObject o;
  o.id = Required<int>(file, node, "id");
  o.name = Required<std::string>(file, node, "name");
  o.object_class = Optional<std::string>(file, node, "class", o.name);
  const std::filesystem::path mesh = Required<std::string>(file, node, "mesh");
  o.mesh_path = mesh.is_absolute() ? mesh : std::filesystem::absolute(file.parent_path() / mesh);
  if (!node["unit"]) throw InputError(Where(file, node), Str("object '", o.name, "' declares no mesh 'unit' (m, cm, mm)"));
  o.unit_scale_to_m = UnitScale(file, node["unit"]);
  if (const YAML::Node culling = node["cull_back_faces"]) {
    try {
      o.back_face_culling = BackFaceCullingFromString(culling.as<std::string>());
    } catch (const InputError& e) {
      throw InputError(Where(file, culling), Str("object '", o.name, "': cull_back_faces ", e.what()));
    }
  }
  if (const YAML::Node body = node["tracker_body"]) {
    o.mounts.push_back({body.as<std::string>(), node["T_body_mesh"] ? Pose(file, node["T_body_mesh"]) : Rigid3d()});
  }
  if (const YAML::Node bodies = node["tracker_bodies"]) {
    if (!bodies.IsSequence()) throw InputError(Where(file, bodies), "'tracker_bodies' must be a list of body names");
    for (const auto& b : bodies) o.mounts.push_back({b.as<std::string>(), Rigid3d()});
  }
  return o;
}

}  // namespace

std::vector<LabelObject> LoadObjectsYaml(const std::filesystem::path& path) {
  const YAML::Node root = LoadYamlFile(path);
  const YAML::Node list = root["objects"];
  if (!list || !list.IsSequence()) throw InputError(Where(path, root), "expected a list 'objects'");
  std::vector<LabelObject> objects;
  for (const auto& node : list) objects.push_back(ParseObject(path, node));
  CheckLabelObjects(objects, path.string());
  return objects;
}

}  // namespace mocap::cli
