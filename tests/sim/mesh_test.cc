#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/check.h"
#include "sim/mesh_check.h"
#include "sim/mesh_generator.h"
#include "sim/sim_objects.h"
#include "sim/ply_writer.h"

namespace mocap::sim {
namespace {

std::string ReadBytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), {}};
}

TEST(MeshBuilder, BoxIsClosedWithExactVolume) {
  MeshBuilder builder;
  builder.AddBox({0.1, 0.2, 0.3}, {1, 2, 3});
  const MeshTopologyReport report = CheckMeshTopology(builder.mesh());
  EXPECT_TRUE(report.watertight());
  EXPECT_EQ(report.edges, 18u);
  EXPECT_NEAR(report.volume_m3, 0.2 * 0.4 * 0.6, 1e-12);
}

TEST(MeshBuilder, LatheCylinderVolumeApproachesPiR2H) {
  MeshBuilder builder;
  builder.AddCylinder(0.05, 0.0, 0.2, 256, {9, 9, 9});
  const MeshTopologyReport report = CheckMeshTopology(builder.mesh());
  EXPECT_TRUE(report.watertight());
  EXPECT_NEAR(report.volume_m3, M_PI * 0.05 * 0.05 * 0.2, 1e-3 * M_PI * 0.05 * 0.05 * 0.2);
}

TEST(MeshBuilder, CheckerFindsAHoleAndAFlippedTriangle) {
  MeshBuilder builder;
  builder.AddBox({0.1, 0.1, 0.1}, {1, 2, 3});
  ColoredMesh holed = builder.mesh();
  holed.triangles.pop_back();
  EXPECT_EQ(CheckMeshTopology(holed).boundary_edges, 3u);
  ColoredMesh flipped = builder.mesh();
  std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
  EXPECT_GT(CheckMeshTopology(flipped).misoriented_edges, 0u);
  EXPECT_FALSE(CheckMeshTopology(flipped).watertight());
}

TEST(MeshGenerator, EveryMeshIsClosedOrientedAndOfItsDeclaredSize) {
  for (const GeneratedMesh& generated : GenerateAllMeshes()) {
    SCOPED_TRACE(generated.name);
    const MeshTopologyReport report = CheckMeshTopology(generated.mesh);
    EXPECT_EQ(report.boundary_edges, 0u);
    EXPECT_EQ(report.non_manifold_edges, 0u);
    EXPECT_EQ(report.misoriented_edges, 0u);
    EXPECT_EQ(report.degenerate_triangles, 0u);
    EXPECT_GT(report.volume_m3, 0.0);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(report.size_m()[k], generated.declared_size_m[k], 0.06 * generated.declared_size_m[k]) << "axis " << k;
    // Objects rest on the face at z = 0 (the table on the floor); the hand is centred on its palm.
    if (generated.name != "hand") {
      EXPECT_NEAR(report.min_m.z(), 0.0, 1e-9);
    }
  }
}

TEST(MeshGenerator, EngineBlockHasAboutTwentyThousandTriangles) {
  const ColoredMesh engine = GenerateEngineBlock();
  EXPECT_GT(engine.triangle_count(), 15000u);
  EXPECT_LT(engine.triangle_count(), 25000u);
}

TEST(MeshGenerator, IsDeterministicToTheByte) {
  const auto first = GenerateAllMeshes();
  const auto second = GenerateAllMeshes();
  ASSERT_EQ(first.size(), second.size());
  for (size_t i = 0; i < first.size(); ++i)
    EXPECT_EQ(EncodePlyBinary(first[i].mesh, "x"), EncodePlyBinary(second[i].mesh, "x")) << first[i].name;
}

TEST(MeshGenerator, PlyLayoutMatchesItsHeader) {
  const ColoredMesh funnel = GenerateFunnel();
  const std::string bytes = EncodePlyBinary(funnel, "unit: metre");
  const size_t header_end = bytes.find("end_header\n");
  ASSERT_NE(header_end, std::string::npos);
  EXPECT_NE(bytes.find(Str("element vertex ", funnel.vertex_count(), "\n")), std::string::npos);
  EXPECT_NE(bytes.find(Str("element face ", funnel.triangle_count(), "\n")), std::string::npos);
  const size_t body = bytes.size() - header_end - 11;
  EXPECT_EQ(body, funnel.vertex_count() * 15 + funnel.triangle_count() * 13);
}

TEST(MeshGenerator, CommittedLibraryIsWhatTheGeneratorWrites) {
  const std::filesystem::path dir = std::filesystem::path(MOCAP_BINARY_DIR) / "sim_test_meshes";
  std::filesystem::remove_all(dir);
  const auto written = WriteMeshLibrary(dir.string());
  EXPECT_EQ(written.size(), GenerateAllMeshes().size());  // objects.yaml: tests/pipeline
  for (const std::string& path : written) {
    const std::filesystem::path name = std::filesystem::path(path).filename();
    SCOPED_TRACE(name.string());
    const std::filesystem::path committed = std::filesystem::path(MOCAP_SOURCE_DIR) / "meshes" / name;
    ASSERT_TRUE(std::filesystem::exists(committed)) << "regenerate with `mocaplabel sim meshes --out meshes`";
    EXPECT_EQ(ReadBytes(path), ReadBytes(committed)) << "meshes/ is stale: regenerate with `mocaplabel sim meshes`";
    EXPECT_LT(std::filesystem::file_size(committed), 1'500'000u);
  }
}

TEST(MeshGenerator, WriteToAnUnwritablePlaceIsAnInputError) {
  EXPECT_THROW(WriteMeshLibrary("/proc/no_such_dir/meshes"), InputError);
}

TEST(SimObjects, DefaultLibraryIsValidAndToolsAreDistinguishable) {
  const SimObjects library = DefaultSimObjects();
  EXPECT_NO_THROW(library.check("default"));
  std::vector<MarkerBody> bodies{DefaultCameraBody()};
  for (const auto& o : library.objects) bodies.push_back(o.body);
  std::vector<std::vector<double>> signatures;
  for (const MarkerBody& body : bodies) {
    std::vector<double> distances;
    for (size_t i = 0; i < body.markers_m.size(); ++i)
      for (size_t j = i + 1; j < body.markers_m.size(); ++j) distances.push_back((body.markers_m[i] - body.markers_m[j]).norm());
    std::sort(distances.begin(), distances.end());
    for (size_t k = 1; k < distances.size(); ++k) EXPECT_GT(distances[k] - distances[k - 1], 0.0025) << body.name;
    signatures.push_back(distances);
  }
  for (size_t a = 0; a < signatures.size(); ++a)
    for (size_t b = a + 1; b < signatures.size(); ++b) {
      double largest = 0;
      for (size_t k = 0; k < signatures[a].size(); ++k) largest = std::max(largest, std::abs(signatures[a][k] - signatures[b][k]));
      EXPECT_GT(largest, 0.005) << bodies[a].name << " vs " << bodies[b].name;
    }
}

TEST(SimObjects, BodyMountsAreNonTrivialAndNearTheirMeshes) {
  for (const SimObject& o : DefaultSimObjects().objects) {
    const Rigid3d T_mesh_body = o.T_body_mesh.inverse();
    EXPECT_GT(T_mesh_body.translation().norm(), 0.05) << o.name;
    EXPECT_GT(RotationDistanceDeg(T_mesh_body, Rigid3d()), 5.0) << o.name;
  }
}

TEST(SimObjects, RejectsDuplicateIdsAndTooFewMarkers) {
  SimObjects library = DefaultSimObjects();
  library.objects[1].id = library.objects[0].id;
  EXPECT_THROW(library.check("x.yaml"), InputError);
  library = DefaultSimObjects();
  library.objects[0].body.markers_m.resize(2);
  EXPECT_THROW(library.check("x.yaml"), InputError);
}

}  // namespace
}  // namespace mocap::sim
