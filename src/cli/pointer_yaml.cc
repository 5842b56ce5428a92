#include "cli/pointer_yaml.h"

#include <cmath>
#include <set>

#include "core/check.h"
#include "pipeline/yaml_read.h"
#include "pipeline/yaml_write.h"

namespace mocap::cli {
namespace {

PointerTool PointerFromDoc(const pipeline::YamlDoc& doc) {
  const pipeline::YamlMap map(doc, doc.root, "pointer", {"pointer_body", "tip_m"});
  PointerTool pointer;
  pointer.body = map.Get<std::string>("pointer_body");
  if (pointer.body.empty()) map.Fail("pointer_body", "must name the pointer's tracker body");
  map.Require("tip_m");
  pointer.tip_m = pipeline::Vector3(doc, map["tip_m"], "tip_m");
  // A tip a metre from its markers is a file in millimetres, not a pointer.
  if (pointer.tip_m.norm() > 1.0) map.Fail("tip_m", "is more than 1 m from the body's origin: metres expected");
  return pointer;
}

double UnitScale(const pipeline::YamlMap& map) {
  const std::string unit = map.Get<std::string>("unit");
  if (unit == "m") return 1.0;
  if (unit == "cm") return 0.01;
  if (unit == "mm") return 0.001;
  map.Fail("unit", "must be m, cm or mm (the unit of the mesh's coordinates)");
}

Landmarks LandmarksFromDoc(const pipeline::YamlDoc& doc) {
  const pipeline::YamlMap map(doc, doc.root, "landmarks file", {"unit", "landmarks"});
  const double scale = UnitScale(map);
  map.Require("landmarks");
  if (!map["landmarks"].IsSequence()) map.Fail("landmarks", "must be a list of {name, mesh}");
  Landmarks landmarks;
  std::set<std::string> seen;
  for (const YAML::Node& node : map["landmarks"]) {
    const pipeline::YamlMap entry(doc, node, "landmark", {"name", "mesh"});
    const std::string name = entry.Get<std::string>("name");
    if (!seen.insert(name).second) entry.Fail("name", "'" + name + "' is listed twice");
    entry.Require("mesh");
    landmarks.names.push_back(name);
    landmarks.p_mesh_m.push_back(scale * pipeline::Vector3(doc, entry["mesh"], "mesh"));
  }
  if (landmarks.names.size() < 3)
    map.Fail("landmarks", Str("lists ", landmarks.names.size(), " points; at least 3 (4 or more recommended) are needed"));
  return landmarks;
}

}  // namespace

PointerTool ReadPointerFile(const std::filesystem::path& path) { return PointerFromDoc(pipeline::LoadYaml(path)); }
PointerTool ParsePointer(const std::string& text, const std::string& file_name) {
  return PointerFromDoc(pipeline::ParseYaml(text, file_name));
}

void WritePointerFile(const PointerTool& pointer, const std::filesystem::path& path, const std::string& comment) {
  YAML::Emitter out;
  if (!comment.empty()) out << YAML::Comment(comment) << YAML::Newline;
  out << YAML::BeginMap << YAML::Key << "pointer_body" << YAML::Value << pointer.body << YAML::Key << "tip_m" << YAML::Value;
  pipeline::EmitVector3(out, pointer.tip_m);
  out << YAML::EndMap;
  MOCAP_CHECK(out.good(), "YAML emitter: ", out.GetLastError());
  pipeline::WriteTextAtomically(path, std::string(out.c_str()) + "\n");
}

Landmarks ReadLandmarksFile(const std::filesystem::path& path) { return LandmarksFromDoc(pipeline::LoadYaml(path)); }
Landmarks ParseLandmarks(const std::string& text, const std::string& file_name) {
  return LandmarksFromDoc(pipeline::ParseYaml(text, file_name));
}

}  // namespace mocap::cli
