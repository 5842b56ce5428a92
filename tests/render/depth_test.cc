// Rendered depth is z along the optical axis in metres: a tilted plane at a known pose, every covered
// pixel unprojected with its rendered depth must lie on the plane.
#include <gtest/gtest.h>

#include <cmath>

#include "render/primitives.h"
#include "render/renderer.h"

namespace mocap {
namespace {

PinholeCamera TestCamera(bool distorted) {
  PinholeCamera cam{640, 480, 525.0, 525.0, 319.5, 239.5, {}};
  if (distorted) cam.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633, 0, 0, 0};
  return cam;
}

void CheckPlaneRoundTrip(bool distorted) {
  const PinholeCamera cam = TestCamera(distorted);
  const auto context = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
  Renderer renderer(*context);
  // A 4 m square plane 1.5 m ahead, tilted 30 degrees about the camera's x axis: covers the whole image.
  const Rigid3d T_camera_plane = Rigid3d::FromRvec({0.5236, 0, 0}, {0.05, -0.02, 1.5});
  const RenderItem item{renderer.Upload(MakeRectangleMesh(4.0, 4.0)), T_camera_plane, 1};
  const RenderOutput out = renderer.Render(cam, std::span(&item, 1));
  const Eigen::Vector3d normal = T_camera_plane.rotation() * Eigen::Vector3d::UnitZ();
  const double offset = normal.dot(T_camera_plane.translation());
  double max_error = 0;
  int covered = 0;
  for (int v = 0; v < cam.height; v += 3) {
    for (int u = 0; u < cam.width; u += 3) {
      const float z = out.depth_m.at(u, v);
      ASSERT_GT(z, 0.0f) << "pixel " << u << "," << v;
      ++covered;
      const Eigen::Vector3d p = cam.Unproject({u, v}, z);
      // Distance to the plane along the pixel's ray, metres.
      max_error = std::max(max_error, std::abs(normal.dot(p) - offset) / std::abs(normal.dot(p.normalized())));
      EXPECT_EQ(out.instance_ids.at(u, v), 1);
    }
  }
  EXPECT_GT(covered, 30000);
  // Without distortion the pixel centre is exact; with it, nearest-neighbour remapping moves the sample
  // by up to half a canvas pixel, ~1.5 mm on this tilted plane at 1.5 m.
  EXPECT_LT(max_error, distorted ? 3e-3 : 1e-4) << "metres";
}

TEST(Depth, TiltedPlaneRoundTrip) { CheckPlaneRoundTrip(false); }
TEST(Depth, TiltedPlaneRoundTripDistorted) { CheckPlaneRoundTrip(true); }

TEST(Depth, NearestObjectWinsAndLayersStayAmodal) {
  const PinholeCamera cam = TestCamera(false);
  const auto context = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
  Renderer renderer(*context);
  const MeshHandle box = renderer.Upload(MakeBoxMesh({0.2, 0.2, 0.2}));
  const std::vector<RenderItem> items = {
      {box, Rigid3d::FromRvec({0, 0, 0}, {0.0, 0.0, 1.0}), 3},   // front face at z = 0.9
      {box, Rigid3d::FromRvec({0, 0, 0}, {0.15, 0.0, 1.5}), 9},  // behind, partly hidden
  };
  const RenderOutput out = renderer.Render(cam, items);
  EXPECT_EQ(out.instance_ids.at(320, 240), 3);
  EXPECT_NEAR(out.depth_m.at(320, 240), 0.9, 1e-5);
  EXPECT_EQ(out.instance_ids.at(360, 240), 3);
  EXPECT_NEAR(out.layers[1].depth_at(360, 240), 1.4, 1e-5) << "the hidden object's own layer is amodal";
  // Front box: 0.2 m at 0.9 m = 116.67 px square, edges at 319.5 +- 58.33 -> pixel centres 262..377 in both axes.
  EXPECT_EQ(out.layers[0].px_count_all, 116 * 116);
  int visible_back = 0;
  for (uint16_t id : out.instance_ids.data) visible_back += id == 9;
  EXPECT_GT(visible_back, 0);
  EXPECT_LT(visible_back, out.layers[1].px_count_all);
}

/// Rendering `mesh` with and without back-face culling gives the same depth image.
void ExpectCullingInvisible(const Mesh& mesh) {
  const PinholeCamera cam = TestCamera(false);
  const RenderItem item{MeshHandle{0}, Rigid3d::FromRvec({0.4, -1.2, 0.3}, {0.02, -0.01, 0.6}), 1};
  RenderOutput culled, full;
  for (bool cull : {false, true}) {
    const auto context = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
    Renderer renderer(*context, {.cull_back_faces = cull});
    ASSERT_EQ(renderer.Upload(mesh).index, 0);
    (cull ? culled : full) = renderer.Render(cam, std::span(&item, 1));
  }
  int differing = 0, covered = 0;
  for (size_t i = 0; i < full.depth_m.data.size(); ++i) {
    covered += full.depth_m.data[i] > 0;
    differing += std::abs(full.depth_m.data[i] - culled.depth_m.data[i]) > 1e-5f;
  }
  EXPECT_GT(covered, 2000) << mesh.source;
  EXPECT_LT(differing, covered / 200) << mesh.source << ": " << differing << " of " << covered << " pixels differ";
}

TEST(Depth, BackFaceCullingKeepsClosedSilhouettes) {
  // Scanned BOP meshes and the generated ones have outward, counter-clockwise faces: culling back faces
  // must not change what the camera sees.
  for (const Mesh& mesh : {LoadMesh(std::string(MOCAP_SHARED_DIR) + "/realdata/bop_lmo_scene2/models/obj_000001.ply", 0.001),
                           MakeBoxMesh({0.1, 0.05, 0.08}), MakeSphereMesh(0.05, 2000)})
    ExpectCullingInvisible(mesh);
}

}  // namespace
}  // namespace mocap
