#include "render/mesh.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/check.h"
#include "render/primitives.h"

namespace mocap {
namespace {

const std::string kModels = std::string(MOCAP_SHARED_DIR) + "/realdata/bop_lmo_scene2/models";

std::string WriteTempObj(const std::string& name, double scale) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream out(path);
  // A tetrahedron with 10-unit edges along the axes.
  out << "v 0 0 0\nv " << 10 * scale << " 0 0\nv 0 " << 10 * scale << " 0\nv 0 0 " << 10 * scale << "\n"
      << "f 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n";
  return path.string();
}

TEST(Mesh, LoadsBopPlyInMillimetresWithColours) {
  const Mesh mesh = LoadMesh(kModels + "/obj_000001.ply", 0.001);
  EXPECT_EQ(mesh.positions_m.size(), 5841u);  // the PLY header's vertex count
  EXPECT_EQ(mesh.triangle_count(), 11678u);
  ASSERT_EQ(mesh.colors.size(), mesh.positions_m.size());
  EXPECT_NEAR(mesh.colors[0].x(), 148.0 / 255.0, 1e-3);  // first vertex: 148 57 57
  EXPECT_NEAR(mesh.positions_m[0].x(), -0.0230565, 1e-6);
  // models_info.json: obj 1 size 75.9 x 77.6 x 91.8 mm; bounding-box diagonal 142.2 mm.
  EXPECT_NEAR(mesh.extent_m(), 0.1422, 0.0005);
  EXPECT_TRUE(mesh.uvs.empty());
}

TEST(Mesh, MillimetreMeshDeclaredAsMetresIsAClearError) {
  try {
    LoadMesh(kModels + "/obj_000001.ply", 1.0);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("obj_000001.ply"), std::string::npos) << what;
    EXPECT_NE(what.find("142."), std::string::npos) << "names the extent: " << what;
    EXPECT_NE(what.find("probably in 'mm'"), std::string::npos) << what;
  }
  const MeshUnitCheck check = CheckMeshUnit(LoadMesh(kModels + "/obj_000001.ply", 1.0, {0, 0}), 1.0);
  EXPECT_FALSE(check.ok);
  EXPECT_EQ(check.likely_unit, "mm");
  EXPECT_DOUBLE_EQ(check.likely_scale_to_m, 0.001);
}

TEST(Mesh, MetreMeshDeclaredAsMillimetresIsTooSmall) {
  const std::string path = WriteTempObj("mocap_mesh_test_m.obj", 0.01);  // 10 cm edges, in metres
  EXPECT_NEAR(LoadMesh(path, 1.0).extent_m(), 0.1 * std::sqrt(3.0), 1e-6);
  try {
    LoadMesh(path, 0.001);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("probably in 'm'"), std::string::npos) << e.what();
  }
}

TEST(Mesh, GeneratedObjInCentimetres) {
  const std::string path = WriteTempObj("mocap_mesh_test_cm.obj", 1.0);  // 10 cm edges, in cm
  const Mesh mesh = LoadMesh(path, 0.01);
  EXPECT_EQ(mesh.triangle_count(), 4u);
  EXPECT_NEAR(mesh.max_m().x(), 0.1, 1e-7);
  EXPECT_TRUE(mesh.colors.empty());
}

TEST(Mesh, MissingFileNamesIt) {
  try {
    LoadMesh("/nonexistent/dir/obj_000042.ply", 0.001);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "/nonexistent/dir/obj_000042.ply");
    EXPECT_NE(std::string(e.what()).find("not found"), std::string::npos);
  }
}

TEST(Mesh, UnreadableFilesAreErrors) {
  const auto dir = std::filesystem::temp_directory_path();
  const std::string not_ply = (dir / "mocap_mesh_test_text.ply").string(), empty = (dir / "mocap_mesh_test_empty.obj").string();
  std::ofstream(not_ply) << "this is not a mesh\n";
  std::ofstream(empty) << "";
  for (const std::string& path : {not_ply, empty}) {
    try {
      LoadMesh(path, 0.001);
      ADD_FAILURE() << "expected InputError for " << path;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where(), path);
      EXPECT_NE(std::string(e.what()).find("cannot read mesh"), std::string::npos) << e.what();
    }
  }
}

TEST(Mesh, UnitNames) {
  EXPECT_EQ(UnitName(0.001), "mm");
  EXPECT_EQ(UnitName(1.0), "m");
  EXPECT_EQ(UnitName(0.0254), "in");
}

TEST(Primitives, BoxAndSphereSizes) {
  const Mesh box = MakeBoxMesh({0.1, 0.2, 0.3});
  EXPECT_EQ(box.triangle_count(), 12u);
  EXPECT_NEAR(box.extent_m(), std::sqrt(0.01 + 0.04 + 0.09), 1e-6);
  const Mesh sphere = MakeSphereMesh(0.05, 20000);
  EXPECT_NEAR(static_cast<double>(sphere.triangle_count()), 20000, 1000);
}

}  // namespace
}  // namespace mocap
