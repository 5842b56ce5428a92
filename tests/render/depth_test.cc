// Rendered depth is z along the optical axis in metres: a tilted plane at a known pose, every covered
// pixel unprojected with its rendered depth must lie on the plane.
#include <gtest/gtest.h>

#include <cmath>

#include "test_camera.h"
#include "core/check.h"
#include "render/primitives.h"
#include "render/renderer.h"

namespace mocap {
namespace {

using test::TestCamera;

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
    Renderer renderer(*context, {.back_face_culling = cull ? BackFaceCulling::kAlways : BackFaceCulling::kNever});
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

/// The sphere without its upper half (an open bowl), tilted so that the camera looks into it.
Mesh BowlMesh() {
  const Mesh sphere = MakeSphereMesh(0.06, 3000);
  Mesh bowl = sphere;
  bowl.indices.clear();
  for (size_t t = 0; t < sphere.indices.size(); t += 3) {
    bool upper = false;
    for (size_t k = 0; k < 3; ++k) upper = upper || sphere.positions_m[sphere.indices[t + k]].z() > 0.0f;
    if (!upper) bowl.indices.insert(bowl.indices.end(), sphere.indices.begin() + t, sphere.indices.begin() + t + 3);
  }
  return bowl;
}

/// Renders `items` (mesh k of `meshes` is handle k) with the given culling choice.
RenderOutput RenderWith(BackFaceCulling culling, const std::vector<Mesh>& meshes, const std::vector<RenderItem>& items,
                        std::vector<bool>* culled = nullptr) {
  const auto context = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
  Renderer renderer(*context, {.back_face_culling = culling});
  for (const Mesh& m : meshes) {
    const MeshHandle h = renderer.Upload(m);
    if (culled) culled->push_back(renderer.CullsBackFaces(h));
  }
  return renderer.Render(TestCamera(false), items);
}

int DifferingPixels(const RenderOutput& a, const RenderOutput& b) {
  int n = 0;
  for (size_t i = 0; i < a.instance_ids.data.size(); ++i)
    n += a.instance_ids.data[i] != b.instance_ids.data[i] || a.depth_m.data[i] != b.depth_m.data[i];
  return n;
}

TEST(Depth, AutomaticCullingKeepsMasksOfClosedAndOpenMeshes) {
  // A closed sphere in front of an open bowl whose inside faces the camera.
  const std::vector<Mesh> meshes = {MakeSphereMesh(0.05, 3000), BowlMesh()};
  const std::vector<RenderItem> items = {{MeshHandle{0}, Rigid3d::FromRvec({0.3, 0.2, 0}, {-0.04, 0.0, 0.6}), 1},
                                         {MeshHandle{1}, Rigid3d::FromRvec({2.6, 0, 0}, {0.05, 0.02, 0.8}), 2}};
  std::vector<bool> culled;
  const RenderOutput all_faces = RenderWith(BackFaceCulling::kNever, meshes, items);
  const RenderOutput automatic = RenderWith(BackFaceCulling::kAuto, meshes, items, &culled);
  EXPECT_EQ(culled, (std::vector<bool>{true, false}));
  int sphere_px = 0, bowl_px = 0;
  for (uint16_t id : all_faces.instance_ids.data) sphere_px += id == 1, bowl_px += id == 2;
  EXPECT_GT(sphere_px, 3000);
  EXPECT_GT(bowl_px, 3000);
  EXPECT_EQ(DifferingPixels(all_faces, automatic), 0);
  for (size_t k = 0; k < items.size(); ++k) EXPECT_EQ(all_faces.layers[k].depth_m, automatic.layers[k].depth_m);
  // Forcing culling on the bowl loses its inside: the check above could fail.
  EXPECT_GT(DifferingPixels(all_faces, RenderWith(BackFaceCulling::kAlways, meshes, items)), 1000);
}

TEST(Depth, NoCullingWithTheCameraInsideAClosedMesh) {
  // A 1 m closed box around the camera: only its inward-facing (back) faces are visible.
  const std::vector<Mesh> meshes = {MakeBoxMesh({1.0, 1.0, 1.0})};
  const std::vector<RenderItem> items = {{MeshHandle{0}, Rigid3d::FromRvec({0.1, 0.2, 0}, {0.05, 0, 0.1}), 1}};
  const RenderOutput all_faces = RenderWith(BackFaceCulling::kNever, meshes, items);
  std::vector<bool> culled;
  const RenderOutput automatic = RenderWith(BackFaceCulling::kAuto, meshes, items, &culled);
  EXPECT_EQ(culled, std::vector<bool>{true});
  int covered = 0;
  for (uint16_t id : all_faces.instance_ids.data) covered += id == 1;
  EXPECT_EQ(covered, 640 * 480);
  EXPECT_EQ(DifferingPixels(all_faces, automatic), 0);
}

}  // namespace
}  // namespace mocap

namespace mocap {
namespace {

TEST(Depth, ACanvasBeyondTheGlLimitIsAClearError) {
  // A 6000x4000 camera with BOP's 3x canvas once aborted on an incomplete framebuffer. 40000 px per side
  // is beyond every OpenGL's renderbuffer limit (llvmpipe: 16384, GPUs: 16384-32768), and the check comes
  // before anything of that size is allocated.
  const PinholeCamera huge{40000, 100, 5000.0, 5000.0, 19999.5, 49.5, {}};
  const auto context = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
  Renderer renderer(*context);
  const RenderItem item{renderer.Upload(MakeBoxMesh({0.2, 0.2, 0.2})), Rigid3d::FromRvec({0, 0, 0}, {0, 0, 1}), 1};
  try {
    renderer.Render(huge, std::span(&item, 1));
    ADD_FAILURE() << "a canvas beyond the GL limit was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("camera 40000x100"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--outside-margin"), std::string::npos) << e.what();
  }
  // The same renderer still renders a camera that fits.
  const PinholeCamera small{64, 48, 50.0, 50.0, 31.5, 23.5, {}};
  EXPECT_EQ(renderer.Render(small, std::span(&item, 1)).instance_ids.at(32, 24), 1);
}

}  // namespace
}  // namespace mocap
