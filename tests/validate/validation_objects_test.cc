// objects.yaml onto the validator's objects (src/cli/validation_objects.h): what `mocaplabel validate`
// compares modulo.
#include "cli/validation_objects.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "core/check.h"

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
  const std::vector<ValidationObject> objects = cli::LoadValidationObjects(file);
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
    EXPECT_THROW(cli::LoadValidationObjects(file), InputError) << bad;
    fs::remove_all(file.parent_path());
  }
}

TEST(ValidationObjects, TheShippedLibraryDeclaresTheFunnelAndTableSymmetries) {
  const std::vector<ValidationObject> objects = cli::LoadValidationObjects(fs::path(MOCAP_SOURCE_DIR) / "meshes/objects.yaml");
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
    symmetric += o.symmetry.has_value();
  }
  EXPECT_EQ(symmetric, 2);
}

}  // namespace
}  // namespace mocap
