// objects.yaml's writer and the stages' views of the object library (object_library.h).
#include <cmath>

#include "core/check.h"
#include "pipeline/object_library.h"
#include "pipeline/yaml_write.h"
#include "render/mesh_closure.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;

void EmitSymmetry(YAML::Emitter& out, const ObjectSymmetry& s) {
  const bool continuous = s.type == ObjectSymmetry::Type::kContinuous;
  out << YAML::BeginMap << YAML::Key << "type" << YAML::Value << (continuous ? "continuous" : "discrete");
  out << YAML::Key << "axis" << YAML::Value;
  EmitVector3(out, s.axis);
  out << YAML::Key << "offset_m" << YAML::Value;
  EmitVector3(out, s.offset_m);
  if (!continuous) {
    out << YAML::Key << "angle_deg" << YAML::Value;
    EmitNumber(out, s.angle_deg);
  }
  out << YAML::EndMap;
}

bool IdentityMounts(const LibraryObject& o) {
  for (const BodyMount& m : o.mounts)
    if (m.T_body_mesh.translation() != Eigen::Vector3d::Zero() || m.T_body_mesh.quat_wxyz() != Eigen::Vector4d(1, 0, 0, 0))
      return false;
  return true;
}

void EmitMounts(YAML::Emitter& out, const LibraryObject& o) {
  if (o.mounts.size() == 1) {
    out << YAML::Key << "tracker_body" << YAML::Value << o.mounts[0].body << YAML::Key << "T_body_mesh" << YAML::Value;
    EmitPose(out, o.mounts[0].T_body_mesh);
    return;
  }
  MOCAP_CHECK(IdentityMounts(o), "object '", o.name, "': several tracker bodies with mounts other than identity");
  out << YAML::Key << "tracker_bodies" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const BodyMount& m : o.mounts) out << m.body;
  out << YAML::EndSeq;
}

void EmitSimulationFields(YAML::Emitter& out, const LibraryObject& o) {
  if (o.markers) {
    out << YAML::Key << "markers_m" << YAML::Value << YAML::BeginSeq;
    for (const Eigen::Vector3d& m : o.markers->markers_m) EmitVector3(out, m);
    out << YAML::EndSeq << YAML::Key << "marker_normal" << YAML::Value;
    EmitVector3(out, o.markers->normal_body);
  }
  if (o.markers || o.reflectivity != 0 || o.tof_deformation_m != 0) {
    out << YAML::Key << "reflectivity" << YAML::Value;
    EmitNumber(out, o.reflectivity);
    out << YAML::Key << "tof_deformation_m" << YAML::Value;
    EmitNumber(out, o.tof_deformation_m);
  }
}

void EmitObject(YAML::Emitter& out, const LibraryObject& o) {
  out << YAML::BeginMap;
  out << YAML::Key << "id" << YAML::Value << o.id << YAML::Key << "name" << YAML::Value << o.name;
  out << YAML::Key << "class" << YAML::Value << o.object_class << YAML::Key << "mesh" << YAML::Value << o.mesh;
  out << YAML::Key << "unit" << YAML::Value << o.unit << YAML::Key << "symmetries" << YAML::Value;
  out << (o.symmetries.empty() ? YAML::Flow : YAML::Block) << YAML::BeginSeq;
  for (const ObjectSymmetry& s : o.symmetries) EmitSymmetry(out, s);
  out << YAML::EndSeq;
  EmitMounts(out, o);
  EmitSimulationFields(out, o);
  if (o.cull_back_faces) out << YAML::Key << "cull_back_faces" << YAML::Value << ToString(*o.cull_back_faces);
  if (o.diameter_m) {
    out << YAML::Key << "diameter_m" << YAML::Value;
    EmitNumber(out, *o.diameter_m);
  }
  if (o.tof_range_biased) out << YAML::Key << "tof_range_biased" << YAML::Value << true;
  out << YAML::EndMap;
}

}  // namespace

std::string EmitObjectLibrary(const ObjectLibrary& library, const std::string& comment) {
  library.check(library.file.empty() ? "object library" : library.file.string());
  YAML::Emitter out;
  if (!comment.empty()) out << YAML::Comment(comment) << YAML::Newline;
  out << YAML::BeginMap << YAML::Key << "objects" << YAML::Value << YAML::BeginSeq;
  for (const LibraryObject& o : library.objects) EmitObject(out, o);
  out << YAML::EndSeq << YAML::EndMap;
  MOCAP_CHECK(out.good(), "YAML emitter: ", out.GetLastError());
  return std::string(out.c_str()) + "\n";
}

void WriteObjectLibrary(const ObjectLibrary& library, const fs::path& path, const std::string& comment) {
  WriteTextAtomically(path, EmitObjectLibrary(library, comment));
}

std::vector<LabelObject> LabelObjectsOf(const ObjectLibrary& library) {
  std::vector<LabelObject> out;
  for (const LibraryObject& o : library.objects)
    out.push_back({o.id, o.name, o.object_class, o.mesh_path, o.unit_scale_to_m, o.mounts, o.cull_back_faces});
  return out;
}

std::vector<ValidationObject> ValidationObjectsOf(const ObjectLibrary& library) {
  std::vector<ValidationObject> out;
  for (const LibraryObject& o : library.objects) {
    std::vector<SymmetryAxis> symmetries;
    for (const ObjectSymmetry& s : o.symmetries)
      symmetries.push_back({s.axis, s.offset_m, s.type == ObjectSymmetry::Type::kContinuous ? 0.0 : s.angle_deg});
    out.push_back(
        {o.id, o.name, o.mesh_path, o.unit_scale_to_m, ChooseValidatorSymmetry(symmetries), o.tof_range_biased});
  }
  return out;
}

sim::SimObjects SimObjectsOf(const ObjectLibrary& library) {
  const std::string where = library.file.empty() ? "object library" : library.file.string();
  sim::SimObjects out;
  for (const LibraryObject& o : library.objects) {
    if (!o.markers || o.mounts.size() != 1)
      throw InputError(where, Str("object '", o.name, "' needs one 'tracker_body' with 'markers_m' for simulation"));
    sim::SimObject s;
    s.id = o.id, s.name = o.name, s.object_class = o.object_class, s.mesh = o.mesh_path.string();
    s.unit_scale_to_m = o.unit_scale_to_m;
    for (const ObjectSymmetry& y : o.symmetries)
      s.symmetries.push_back({y.type == ObjectSymmetry::Type::kContinuous ? sim::Symmetry::Type::kContinuous
                                                                           : sim::Symmetry::Type::kDiscrete,
                              y.axis, y.offset_m, y.angle_deg});
    s.body = {o.mounts[0].body, o.markers->markers_m, o.markers->normal_body};
    s.T_body_mesh = o.mounts[0].T_body_mesh;
    s.reflectivity = o.reflectivity, s.tof_deformation_m = o.tof_deformation_m;
    s.tof_range_biased = o.tof_range_biased;
    out.objects.push_back(s);
  }
  out.check(where);
  return out;
}

ObjectLibrary LibraryOfSimObjects(const sim::SimObjects& objects, const fs::path& mesh_dir, const fs::path& yaml_dir) {
  ObjectLibrary library;
  for (const sim::SimObject& s : objects.objects) {
    LibraryObject o;
    o.id = s.id, o.name = s.name, o.object_class = s.object_class.empty() ? s.name : s.object_class;
    o.mesh_path = fs::absolute(mesh_dir / s.mesh).lexically_normal();
    o.mesh = fs::relative(o.mesh_path, fs::absolute(yaml_dir)).generic_string();
    o.unit_scale_to_m = s.unit_scale_to_m;
    o.unit = s.unit_scale_to_m == 1.0 ? "m" : s.unit_scale_to_m == 0.01 ? "cm" : "mm";
    for (const sim::Symmetry& y : s.symmetries)
      o.symmetries.push_back({y.type == sim::Symmetry::Type::kContinuous ? ObjectSymmetry::Type::kContinuous
                                                                          : ObjectSymmetry::Type::kDiscrete,
                              y.axis, y.offset_m, y.angle_deg});
    o.mounts.push_back({s.body.name, s.T_body_mesh});
    o.markers = ObjectMarkers{s.body.markers_m, s.body.normal_body};
    o.reflectivity = s.reflectivity, o.tof_deformation_m = s.tof_deformation_m;
    o.tof_range_biased = s.tof_range_biased;
    library.objects.push_back(o);
  }
  return library;
}

ObjectLibrary LibraryOfBopObjects(const std::vector<import::BopObject>& objects) {
  ObjectLibrary library;
  for (const import::BopObject& b : objects) {
    LibraryObject o;
    o.id = b.id, o.name = b.name, o.object_class = b.name;
    o.mesh = b.mesh.string(), o.mesh_path = b.mesh;
    o.unit = "mm", o.unit_scale_to_m = 0.001;
    for (const std::string& body : b.bodies) o.mounts.push_back({body, Rigid3d()});
    o.diameter_m = b.diameter_m;
    library.objects.push_back(o);
  }
  return library;
}

void WriteBopObjects(const fs::path& file, const std::vector<import::BopObject>& objects, const std::string& source) {
  WriteObjectLibrary(LibraryOfBopObjects(objects), file,
                     "Objects of " + source + " (BOP obj_id, mesh in mm; T_body_mesh is identity)");
}

}  // namespace mocap::pipeline
