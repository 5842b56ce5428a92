// The object library (pipeline/object_library.h): its strict reader, its writer, and the views the
// validator and the simulator take of it.
#include "pipeline/object_library.h"
#include "pipeline/record_stage.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "core/check.h"
#include "render/mesh_closure.h"
#include "sim/sim_objects.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

/// An objects.yaml in a fresh folder with one object per entry of `symmetries` (YAML text of the list).
fs::path WriteLibrary(const std::string& name, const std::vector<std::string>& symmetries) {
  const fs::path dir = fs::temp_directory_path() / ("mocaplabel_validation_objects_" + name + "_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream out(dir / "objects.yaml");
  out << "objects:\n";
  for (size_t i = 0; i < symmetries.size(); ++i)
    out << "  - id: " << i + 1 << "\n    name: object" << i + 1 << "\n    mesh: object.ply\n    unit: mm\n"
        << "    tracker_body: body" << i + 1 << "\n    symmetries: " << symmetries[i] << "\n";
  return dir / "objects.yaml";
}

TEST(ValidationObjects, CarryTheDeclaredSymmetries) {
  const fs::path file = WriteLibrary("ok", {
      "[]",
      "[{type: continuous, axis: [0, 0, 2], offset_m: [0.01, 0, 0]}]",
      "[{type: discrete, axis: [0, 1, 0], angle_deg: 180}]",
      "[{type: discrete, axis: [1, 0, 0], angle_deg: 90}, {type: continuous, axis: [0, 1, 0]}]",
  });
  const std::vector<ValidationObject> objects = pipeline::ValidationObjectsOf(pipeline::ReadObjectLibrary(file));
  ASSERT_EQ(objects.size(), 4u);
  EXPECT_EQ(objects[0].id, 1);
  EXPECT_DOUBLE_EQ(objects[0].unit_scale_to_m, 0.001);
  EXPECT_FALSE(objects[0].symmetry.has_value());
  ASSERT_TRUE(objects[1].symmetry.has_value());
  EXPECT_TRUE(objects[1].symmetry->axis_object.isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(objects[1].symmetry->point_object.isApprox(Eigen::Vector3d(0.01, 0, 0)));
  EXPECT_EQ(objects[1].symmetry->step_deg, 0.0);
  ASSERT_TRUE(objects[2].symmetry.has_value());
  EXPECT_EQ(objects[2].symmetry->step_deg, 180.0);
  ASSERT_TRUE(objects[3].symmetry.has_value());  // the continuous one wins over the discrete one
  EXPECT_EQ(objects[3].symmetry->step_deg, 0.0);
  EXPECT_TRUE(objects[3].symmetry->axis_object.isApprox(Eigen::Vector3d::UnitY()));
  fs::remove_all(file.parent_path());
}

TEST(ValidationObjects, RejectMalformedSymmetries) {
  for (const char* bad : {"[{type: discrete, axis: [0, 0, 1], angle_deg: 70}]", "[{type: mirror, axis: [0, 0, 1]}]",
                                 "[{type: continuous, axis: [0, 0, 0]}]", "[{type: continuous}]"}) {
    const fs::path file = WriteLibrary("bad", {bad});
    EXPECT_THROW(pipeline::ValidationObjectsOf(pipeline::ReadObjectLibrary(file)), InputError) << bad;
    fs::remove_all(file.parent_path());
  }
}

TEST(ValidationObjects, TheShippedLibraryDeclaresTheFunnelAndTableSymmetries) {
  const std::vector<ValidationObject> objects = pipeline::ValidationObjectsOf(pipeline::ReadObjectLibrary(fs::path(MOCAP_SOURCE_DIR) / "meshes/objects.yaml"));
  int symmetric = 0;
  for (const ValidationObject& o : objects) {
    if (o.name == "funnel") {
      ASSERT_TRUE(o.symmetry.has_value());
      EXPECT_EQ(o.symmetry->step_deg, 0.0);
      EXPECT_TRUE(o.symmetry->axis_object.isApprox(Eigen::Vector3d::UnitZ()));
    }
    if (o.name == "table") {
      ASSERT_TRUE(o.symmetry.has_value());
      EXPECT_EQ(o.symmetry->step_deg, 180.0);
    }
    EXPECT_EQ(o.tof_range_biased, o.name == "oil_bottle") << o.name;
    symmetric += o.symmetry.has_value();
  }
  EXPECT_EQ(symmetric, 2);
}

TEST(ObjectLibrary, CommittedObjectsYamlIsWhatTheWriterWrites) {
  const fs::path dir = fs::temp_directory_path() / ("mocaplabel_builtin_library_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path written = pipeline::WriteBuiltInObjectLibrary(dir);
  std::ifstream a(written), b(fs::path(MOCAP_SOURCE_DIR) / "meshes" / "objects.yaml");
  const std::string generated((std::istreambuf_iterator<char>(a)), {}), committed((std::istreambuf_iterator<char>(b)), {});
  EXPECT_EQ(generated, committed) << "meshes/objects.yaml is stale: regenerate with `mocaplabel sim meshes --out meshes`";
  fs::remove_all(dir);
}

TEST(ObjectLibrary, CommittedObjectsYamlIsTheBuiltInLibrary) {
  const sim::SimObjects parsed = pipeline::SimObjectsOf(pipeline::ReadObjectLibrary(fs::path(MOCAP_SOURCE_DIR) / "meshes" / "objects.yaml"));
  const sim::SimObjects built = sim::DefaultSimObjects();
  ASSERT_EQ(parsed.objects.size(), built.objects.size());
  for (size_t i = 0; i < built.objects.size(); ++i) {
    SCOPED_TRACE(built.objects[i].name);
    EXPECT_EQ(parsed.objects[i].name, built.objects[i].name);
    EXPECT_EQ(parsed.objects[i].id, built.objects[i].id);
    EXPECT_EQ(parsed.objects[i].symmetries.size(), built.objects[i].symmetries.size());
    EXPECT_EQ(parsed.objects[i].T_body_mesh.translation(), built.objects[i].T_body_mesh.translation());  // round trip
    EXPECT_LT(RotationDistanceDeg(parsed.objects[i].T_body_mesh, built.objects[i].T_body_mesh), 1e-6);
    EXPECT_DOUBLE_EQ(parsed.objects[i].reflectivity, built.objects[i].reflectivity);
    for (size_t m = 0; m < built.objects[i].body.markers_m.size(); ++m)
      EXPECT_EQ(parsed.objects[i].body.markers_m[m], built.objects[i].body.markers_m[m]);
  }
}


/// The error a library text gives (its message), or "" when it parses.
std::string LibraryError(const std::string& text) {
  try {
    pipeline::ParseObjectLibrary(text, "objects.yaml", "/meshes");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* kObject = "objects:\n  - id: 1\n    name: box\n    mesh: box.ply\n    unit: mm\n    tracker_body: box_body\n";

TEST(ObjectLibrary, StrictReaderNamesFileLineAndKey) {
  EXPECT_EQ(LibraryError(kObject), "");
  // A misspelt key: its line and a "did you mean".
  const std::string typo = LibraryError(std::string(kObject) + "    T_body_mehs: {translation_m: [0, 0, 0], rotation_wxyz: [1, 0, 0, 0]}\n");
  EXPECT_NE(typo.find("objects.yaml:7"), std::string::npos) << typo;
  EXPECT_NE(typo.find("'T_body_mehs'"), std::string::npos) << typo;
  EXPECT_NE(typo.find("did you mean 'T_body_mesh'"), std::string::npos) << typo;
  // A wrong type.
  const std::string type = LibraryError("objects:\n  - id: one\n    name: box\n    mesh: box.ply\n    unit: mm\n    tracker_body: b\n");
  EXPECT_NE(type.find("objects.yaml:2"), std::string::npos) << type;
  EXPECT_NE(type.find("'id'"), std::string::npos) << type;
  // A rotation that is not a rotation.
  const std::string rotation =
      LibraryError(std::string(kObject) + "    T_body_mesh:\n      translation_m: [0, 0, 0]\n      rotation_wxyz: [1, 1, 0, 0]\n");
  EXPECT_NE(rotation.find("objects.yaml:9"), std::string::npos) << rotation;
  EXPECT_NE(rotation.find("rotation_wxyz"), std::string::npos) << rotation;
  EXPECT_NE(rotation.find("not a rotation"), std::string::npos) << rotation;
  // A unit that is not a unit.
  const std::string unit = LibraryError("objects:\n  - id: 1\n    name: box\n    mesh: box.ply\n    unit: furlong\n    tracker_body: b\n");
  EXPECT_NE(unit.find("objects.yaml:5"), std::string::npos) << unit;
  EXPECT_NE(unit.find("'unit'"), std::string::npos) << unit;
  // Values out of range, duplicates and structure.
  EXPECT_NE(LibraryError("objects:\n  - {id: 0, name: a, mesh: a.ply, unit: m, tracker_body: b}\n").find("objects.yaml:2"), std::string::npos);
  EXPECT_NE(LibraryError("objects:\n  - {id: 1, name: a, mesh: a.ply, unit: m, tracker_body: b}\n"
                         "  - {id: 1, name: c, mesh: a.ply, unit: m, tracker_body: d}\n").find("appears twice"), std::string::npos);
  EXPECT_NE(LibraryError("object:\n  - {id: 1}\n").find("did you mean 'objects'"), std::string::npos);
  EXPECT_NE(LibraryError("objects: [{id: 1, name: a, mesh: a.ply, unit: m}]\n").find("tracker_body"), std::string::npos);
  const std::string shine = LibraryError("objects:\n  - {id: 1, name: a, mesh: a.ply, unit: m, tracker_body: b,\n     tof_range_biased: shiny}\n");
  EXPECT_NE(shine.find("objects.yaml:3"), std::string::npos) << shine;
  EXPECT_NE(shine.find("tof_range_biased"), std::string::npos) << shine;
}

TEST(ObjectLibrary, WrittenAndReadBackIsTheSameLibrary) {
  const fs::path dir = fs::temp_directory_path() / ("mocaplabel_library_roundtrip_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  pipeline::ObjectLibrary built = pipeline::LibraryOfSimObjects(sim::DefaultSimObjects(), dir / "meshes", dir);
  built.objects[0].cull_back_faces = BackFaceCulling::kAlways;
  built.objects[1].diameter_m = 0.2;
  pipeline::WriteObjectLibrary(built, dir / "objects.yaml", "a comment");
  const pipeline::ObjectLibrary read = pipeline::ReadObjectLibrary(dir / "objects.yaml");
  EXPECT_EQ(pipeline::EmitObjectLibrary(read, "a comment"), pipeline::EmitObjectLibrary(built, "a comment"));
  ASSERT_EQ(read.objects.size(), built.objects.size());
  for (size_t i = 0; i < read.objects.size(); ++i) {
    EXPECT_EQ(read.objects[i].mesh_path, built.objects[i].mesh_path);
    EXPECT_EQ(read.objects[i].mounts[0].T_body_mesh.translation(), built.objects[i].mounts[0].T_body_mesh.translation());
  }
  EXPECT_EQ(read.objects[0].cull_back_faces, BackFaceCulling::kAlways);
  EXPECT_EQ(read.objects[1].diameter_m, 0.2);
  EXPECT_TRUE(read.objects[0].tof_range_biased);  // the oil bottle declares its shine
  EXPECT_FALSE(read.objects[1].tof_range_biased);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mocap
