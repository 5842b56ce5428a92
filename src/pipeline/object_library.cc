#include "pipeline/object_library.h"

#include <cmath>
#include <set>

#include "core/check.h"
#include "pipeline/yaml_read.h"
#include "pipeline/yaml_write.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;

ObjectSymmetry ParseSymmetry(const YamlDoc& doc, const YAML::Node& node, const std::string& object) {
  const YamlMap map(doc, node, Str("a symmetry of '", object, "'"), {"type", "axis", "offset_m", "angle_deg"});
  ObjectSymmetry s;
  const std::string type = map.Get<std::string>("type");
  if (type != "continuous" && type != "discrete") map.Fail("type", Str("must be continuous or discrete (got '", type, "')"));
  s.type = type == "continuous" ? ObjectSymmetry::Type::kContinuous : ObjectSymmetry::Type::kDiscrete;
  map.Require("axis");
  s.axis = Vector3(doc, map["axis"], "axis");
  if (!(s.axis.norm() > 1e-9)) map.Fail("axis", "must not be zero");
  s.axis.normalize();
  if (map.Has("offset_m")) s.offset_m = Vector3(doc, map["offset_m"], "offset_m");
  if (s.type == ObjectSymmetry::Type::kContinuous) {
    if (map.Has("angle_deg")) map.Fail("angle_deg", "is for discrete symmetries only");
    return s;
  }
  s.angle_deg = map.Get<double>("angle_deg");
  const double count = 360.0 / s.angle_deg;
  if (!(s.angle_deg > 0 && s.angle_deg < 360) || std::abs(count - std::round(count)) > 1e-6)
    map.Fail("angle_deg", "must divide 360 (180, 120, 90, ...)");
  return s;
}

void ParseMounts(const YamlMap& map, const std::string& name, LibraryObject& o) {
  if (map.Has("tracker_body") && map.Has("tracker_bodies")) map.Fail("tracker_bodies", "and 'tracker_body' exclude each other");
  if (map.Has("tracker_body")) {
    const Rigid3d T_body_mesh = map.Has("T_body_mesh") ? Pose(map.doc(), map["T_body_mesh"], "T_body_mesh") : Rigid3d();
    o.mounts.push_back({map.Get<std::string>("tracker_body"), T_body_mesh});
    return;
  }
  if (map.Has("T_body_mesh")) map.Fail("T_body_mesh", "needs 'tracker_body' (tracker_bodies are mounted at identity)");
  if (!map.Has("tracker_bodies")) throw InputError(map.Where(), Str("object '", name, "' names no 'tracker_body'"));
  const YAML::Node bodies = map["tracker_bodies"];
  if (!bodies.IsSequence() || bodies.size() == 0) map.Fail("tracker_bodies", "must be a non-empty list of body names");
  for (const auto& b : bodies) o.mounts.push_back({As<std::string>(map.doc(), b, "tracker_bodies"), Rigid3d()});
}

void ParseSimulationFields(const YamlMap& map, LibraryObject& o) {
  if (map.Has("markers_m")) {
    const YAML::Node list = map["markers_m"];
    if (!list.IsSequence()) map.Fail("markers_m", "must be a list of [x, y, z]");
    ObjectMarkers markers;
    for (const auto& m : list) markers.markers_m.push_back(Vector3(map.doc(), m, "markers_m"));
    if (map.Has("marker_normal")) {
      const Eigen::Vector3d normal = Vector3(map.doc(), map["marker_normal"], "marker_normal");
      if (!(normal.norm() > 1e-9)) map.Fail("marker_normal", "must not be zero");
      markers.normal_body = normal.normalized();
    }
    o.markers = markers;
  } else if (map.Has("marker_normal")) {
    map.Fail("marker_normal", "needs 'markers_m'");
  }
  o.reflectivity = map.Get<double>("reflectivity", 0.0);
  if (o.reflectivity < 0 || o.reflectivity > 1) map.Fail("reflectivity", "must be in [0, 1]");
  o.tof_deformation_m = map.Get<double>("tof_deformation_m", 0.0);
  if (o.tof_deformation_m < 0 || o.tof_deformation_m > 0.2) map.Fail("tof_deformation_m", "must be in [0, 0.2] m");
}

LibraryObject ParseObject(const YamlDoc& doc, const YAML::Node& node, const fs::path& base_dir, size_t index) {
  const YamlMap map(doc, node, Str("object ", index + 1),
                    {"id", "name", "class", "mesh", "unit", "symmetries", "tracker_body", "tracker_bodies", "T_body_mesh",
                     "markers_m", "marker_normal", "reflectivity", "tof_deformation_m", "cull_back_faces", "diameter_m",
                     "tof_range_biased"});
  LibraryObject o;
  o.id = map.Get<int>("id");
  if (o.id < 1 || o.id > 65535) map.Fail("id", Str(o.id, " is outside 1..65535"));
  o.name = map.Get<std::string>("name");
  if (o.name.empty()) map.Fail("name", "is empty");
  o.object_class = map.Get<std::string>("class", o.name);
  o.mesh = map.Get<std::string>("mesh");
  o.mesh_path = fs::path(o.mesh).is_absolute() ? fs::path(o.mesh) : fs::absolute(base_dir / o.mesh).lexically_normal();
  map.Require("unit");
  o.unit_scale_to_m = LengthUnit(doc, map["unit"], "unit");
  o.unit = map.Get<std::string>("unit");
  if (map.Has("symmetries")) {
    if (!map["symmetries"].IsSequence()) map.Fail("symmetries", "must be a list");
    for (const auto& s : map["symmetries"]) o.symmetries.push_back(ParseSymmetry(doc, s, o.name));
  }
  ParseMounts(map, o.name, o);
  ParseSimulationFields(map, o);
  if (map.Has("cull_back_faces")) {
    try {
      o.cull_back_faces = BackFaceCullingFromString(map.Get<std::string>("cull_back_faces"));
    } catch (const InputError& e) {
      map.Fail("cull_back_faces", e.what());
    }
  }
  if (map.Has("diameter_m")) {
    o.diameter_m = map.Get<double>("diameter_m");
    if (!(*o.diameter_m > 0)) map.Fail("diameter_m", "must be positive");
  }
  o.tof_range_biased = map.Get<bool>("tof_range_biased", false);
  return o;
}

}  // namespace

const LibraryObject* ObjectLibrary::Find(const std::string& name) const {
  for (const LibraryObject& o : objects)
    if (o.name == name) return &o;
  return nullptr;
}

const LibraryObject* ObjectLibrary::FindId(int id) const {
  for (const LibraryObject& o : objects)
    if (o.id == id) return &o;
  return nullptr;
}

void ObjectLibrary::check(const std::string& where) const {
  CheckLabelObjects(LabelObjectsOf(*this), where);  // ids, names, bodies unique; every object mounted
  for (const LibraryObject& o : objects)
    if (o.markers) sim::MarkerBody{o.mounts.front().body, o.markers->markers_m, o.markers->normal_body}.check(where);
}

static ObjectLibrary LibraryFromDoc(const YamlDoc& doc, const fs::path& base_dir) {
  const YamlMap root(doc, doc.root, "the object library", {"objects"});
  root.Require("objects");
  if (!root["objects"].IsSequence()) root.Fail("objects", "must be a list of objects");
  ObjectLibrary library;
  library.file = doc.file;
  for (size_t i = 0; i < root["objects"].size(); ++i)
    library.objects.push_back(ParseObject(doc, root["objects"][i], base_dir, i));
  library.check(doc.file);
  return library;
}

ObjectLibrary ParseObjectLibrary(const std::string& text, const std::string& file_name, const fs::path& base_dir) {
  return LibraryFromDoc(ParseYaml(text, file_name), base_dir);
}

ObjectLibrary ReadObjectLibrary(const fs::path& path) {
  ObjectLibrary library = LibraryFromDoc(LoadYaml(path), fs::absolute(path).parent_path());
  library.file = path;
  return library;
}

}  // namespace mocap::pipeline
