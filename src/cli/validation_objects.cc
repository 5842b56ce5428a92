#include "cli/validation_objects.h"

#include <cmath>
#include <map>
#include <optional>
#include <string>

#include "cli/objects_yaml.h"
#include "cli/yaml_util.h"
#include "core/check.h"

namespace mocap::cli {
namespace {

namespace fs = std::filesystem;

/// One entry of `symmetries`: {type: continuous|discrete, axis, offset_m, angle_deg (discrete)}.
SymmetryAxis ParseSymmetry(const fs::path& file, const YAML::Node& node) {
  const std::string type = Required<std::string>(file, node, "type");
  if (type != "continuous" && type != "discrete")
    throw InputError(Where(file, node), "symmetry 'type' must be continuous or discrete");
  if (!node["axis"]) throw InputError(Where(file, node), "symmetry without 'axis'");
  SymmetryAxis s;
  s.axis_object = Vector3(file, node["axis"]);
  if (!(s.axis_object.norm() > 1e-9)) throw InputError(Where(file, node), "symmetry 'axis' must not be zero");
  s.axis_object.normalize();
  if (node["offset_m"]) s.point_object = Vector3(file, node["offset_m"]);
  if (type == "continuous") return s;
  s.step_deg = Required<double>(file, node, "angle_deg");
  const double count = 360.0 / s.step_deg;
  if (!(s.step_deg > 0 && s.step_deg < 360) || std::abs(count - std::round(count)) > 1e-6)
    throw InputError(Where(file, node), "discrete symmetry 'angle_deg' must divide 360 (180, 120, 90, ...)");
  return s;
}

/// The symmetry the validator uses for an object's `symmetries` list (none when absent or empty).
std::optional<SymmetryAxis> ChooseSymmetry(const fs::path& file, const YAML::Node& list) {
  if (!list) return std::nullopt;
  if (!list.IsSequence()) throw InputError(Where(file, list), "'symmetries' must be a list");
  std::vector<SymmetryAxis> symmetries;
  for (const auto& node : list) symmetries.push_back(ParseSymmetry(file, node));
  return ChooseValidatorSymmetry(symmetries);
}

}  // namespace

std::vector<ValidationObject> LoadValidationObjects(const fs::path& path) {
  const std::vector<LabelObject> labelled = LoadObjectsYaml(path);  // the file's structure checked here
  std::map<std::string, std::optional<SymmetryAxis>> symmetry_of;
  for (const auto& node : LoadYamlFile(path)["objects"])
    symmetry_of[Required<std::string>(path, node, "name")] = ChooseSymmetry(path, node["symmetries"]);
  std::vector<ValidationObject> objects;
  for (const LabelObject& o : labelled)
    objects.push_back({o.id, o.name, o.mesh_path, o.unit_scale_to_m, symmetry_of.at(o.name)});
  return objects;
}

}  // namespace mocap::cli
