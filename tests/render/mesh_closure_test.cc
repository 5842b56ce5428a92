// AnalyzeClosure tells meshes where back-face culling is exact (closed, consistently and outward wound)
// from those where it is not, on generated and real meshes.
#include "render/mesh_closure.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "render/primitives.h"

namespace mocap {
namespace {

const std::string kShared = std::string(MOCAP_SHARED_DIR) + "/realdata/";

/// Every triangle's winding reversed.
Mesh Inverted(Mesh mesh) {
  for (size_t t = 0; t < mesh.indices.size(); t += 3) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
  return mesh;
}

/// The sphere without the triangles of its upper half: an open bowl.
Mesh Bowl() {
  const Mesh sphere = MakeSphereMesh(0.05, 2000);
  Mesh bowl = sphere;
  bowl.indices.clear();
  for (size_t t = 0; t < sphere.indices.size(); t += 3) {
    const bool upper = std::max({sphere.positions_m[sphere.indices[t]].z(), sphere.positions_m[sphere.indices[t + 1]].z(),
                                 sphere.positions_m[sphere.indices[t + 2]].z()}) > 0.0f;
    if (!upper) bowl.indices.insert(bowl.indices.end(), sphere.indices.begin() + t, sphere.indices.begin() + t + 3);
  }
  return bowl;
}

TEST(MeshClosure, GeneratedClosedMeshesAreCullable) {
  const MeshClosure box = AnalyzeClosure(MakeBoxMesh({0.1, 0.2, 0.3}));
  EXPECT_TRUE(box.culling_exact()) << box.Describe();
  EXPECT_EQ(box.shells, 1);
  EXPECT_NEAR(box.volume_m3, 0.1 * 0.2 * 0.3, 1e-9);
  // The UV sphere has a ring of vertices at each pole, all at one position: only welding closes it.
  const MeshClosure sphere = AnalyzeClosure(MakeSphereMesh(0.05, 2000));
  EXPECT_TRUE(sphere.culling_exact()) << sphere.Describe();
  EXPECT_EQ(sphere.welded_vertices + 2 * (2 * 22 - 1), static_cast<int64_t>(MakeSphereMesh(0.05, 2000).positions_m.size()));
}

TEST(MeshClosure, SplitSeamVerticesAreWelded) {
  // A box with its own 3 vertices per triangle (as loaders split vertices at colour or UV seams).
  const Mesh box = MakeBoxMesh({0.1, 0.1, 0.1});
  Mesh split;
  for (uint32_t i : box.indices) {
    split.indices.push_back(static_cast<uint32_t>(split.positions_m.size()));
    split.positions_m.push_back(box.positions_m[i]);
  }
  const MeshClosure closure = AnalyzeClosure(split);
  EXPECT_TRUE(closure.culling_exact()) << closure.Describe();
  EXPECT_EQ(closure.welded_vertices, 8);
}

TEST(MeshClosure, OpenFlippedAndInwardMeshesAreNot) {
  Mesh holed = MakeBoxMesh({0.1, 0.1, 0.1});
  holed.indices.resize(holed.indices.size() - 3);  // one triangle missing
  EXPECT_EQ(AnalyzeClosure(holed).boundary_edges, 3);
  EXPECT_FALSE(AnalyzeClosure(holed).culling_exact());

  Mesh flipped = MakeBoxMesh({0.1, 0.1, 0.1});
  std::swap(flipped.indices[1], flipped.indices[2]);  // one triangle wound the other way
  EXPECT_EQ(AnalyzeClosure(flipped).misoriented_edges, 3);
  EXPECT_FALSE(AnalyzeClosure(flipped).culling_exact());

  const MeshClosure inward = AnalyzeClosure(Inverted(MakeSphereMesh(0.05, 2000)));
  EXPECT_EQ(inward.boundary_edges + inward.misoriented_edges + inward.nonmanifold_edges, 0);
  EXPECT_EQ(inward.inward_shells, 1);
  EXPECT_LT(inward.volume_m3, 0);
  EXPECT_FALSE(inward.culling_exact());

  EXPECT_FALSE(AnalyzeClosure(Bowl()).culling_exact());
  EXPECT_FALSE(AnalyzeClosure(MakeDiscMesh(0.05)).culling_exact());
  EXPECT_FALSE(AnalyzeClosure(MakeRectangleMesh(0.1, 0.1)).culling_exact());
}

TEST(MeshClosure, TwoShellsAndACavity) {
  Mesh two = MakeBoxMesh({0.1, 0.1, 0.1});
  const Mesh ball = MakeSphereMesh(0.03, 500);
  const auto base = static_cast<uint32_t>(two.positions_m.size());
  for (const auto& p : ball.positions_m) two.positions_m.push_back(p + Eigen::Vector3f(0.2f, 0, 0));
  for (uint32_t i : ball.indices) two.indices.push_back(base + i);
  EXPECT_TRUE(AnalyzeClosure(two).culling_exact());
  EXPECT_EQ(AnalyzeClosure(two).shells, 2);
  // The ball inside the box, inward: a hollow box. Culling would be exact, the check is conservative.
  Mesh hollow = MakeBoxMesh({0.1, 0.1, 0.1});
  for (const auto& p : ball.positions_m) hollow.positions_m.push_back(p);
  const Mesh inward_ball = Inverted(ball);
  for (uint32_t i : inward_ball.indices) hollow.indices.push_back(base + i);
  EXPECT_FALSE(AnalyzeClosure(hollow).culling_exact());
}

TEST(MeshClosure, RealMeshes) {
  // The Stanford bunny's zippered scan has holes in its base.
  const MeshClosure bunny = AnalyzeClosure(LoadMesh(kShared + "stanford_bunny/reconstruction/bun_zipper_res3.ply", 1.0));
  EXPECT_GT(bunny.boundary_edges, 0);
  EXPECT_FALSE(bunny.culling_exact());
  // LM-O's ape: a closed, outward scan.
  const MeshClosure ape = AnalyzeClosure(LoadMesh(kShared + "bop_lmo_scene2/models/obj_000001.ply", 0.001));
  EXPECT_TRUE(ape.culling_exact()) << ape.Describe();
  // The shipped library: unions of closed, outward shells (docs/objects.md).
  for (const char* name : {"oil_bottle", "funnel", "engine_block", "table", "hand"}) {
    const MeshClosure c = AnalyzeClosure(LoadMesh(std::string(MOCAP_SOURCE_DIR) + "/meshes/" + name + ".ply", 1.0));
    EXPECT_TRUE(c.culling_exact()) << name << ": " << c.Describe();
  }
}

}  // namespace
}  // namespace mocap
