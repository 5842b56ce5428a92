#include "validate/model_crop.h"

#include <gtest/gtest.h>

#include "validate/acquisition.h"
#include "synthetic.h"

namespace mocap {
namespace {

/// A closed box mesh (12 triangles) centred at the origin.
TriangleMesh BoxMesh(const Eigen::Vector3d& size_m) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.vertices.push_back(Eigen::Vector3d((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 0.5 : -0.5)
                                .cwiseProduct(size_m));
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& f : faces) {
    mesh.triangles.push_back({f[0], f[1], f[2]});
    mesh.triangles.push_back({f[0], f[2], f[3]});
  }
  return mesh;
}

TEST(ModelCrop, ZBufferKeepsOnlyTheFacingSide) {
  const SurfaceCropSource source = SurfaceCropSource::FromMesh(BoxMesh({0.1, 0.1, 0.1}), CropOptions{});
  // Camera 1 m in front of the z = +5 cm face, looking at it straight on: only that face is visible.
  const Rigid3d T_camera_model = LookAt({0, 0, 1.0}, {0, 0, 0}, {0, 1, 0});
  const ModelCrop crop = source.Crop(T_camera_model);
  ASSERT_FALSE(crop.points_model.empty());
  for (const auto& p : crop.points_model) EXPECT_NEAR(p.z(), 0.05, 1e-9);
  // About one point per 5 mm pixel over a 10 cm face: (10 cm / 5 mm + 1)^2 = 441.
  EXPECT_NEAR(static_cast<double>(crop.points_model.size()), 441.0, 50.0);
  EXPECT_NEAR(crop.view_direction_model.z(), 1.0, 1e-9);
}


TEST(ModelCrop, MeshCheckRejectsBadIndices) {
  TriangleMesh mesh = BoxMesh({0.1, 0.1, 0.1});
  mesh.triangles.push_back({0, 1, 99});
  EXPECT_THROW(mesh.check(), InputError);
  EXPECT_THROW(TriangleMesh{}.check(), InputError);
}

TEST(Acquisition, ViewSphereFindsABoxPoseWithoutAPrior) {
  // An elongated box (no symmetric ambiguity beyond the box's own 180-degree flips) seen by a camera.
  const TriangleMesh mesh = BoxMesh({0.16, 0.06, 0.21});
  const SurfaceCropSource source = SurfaceCropSource::FromMesh(mesh, CropOptions{});
  const Rigid3d T_camera_model = Rigid3d::FromRvec({0.9, 0.3, -0.2}, {0.05, -0.02, 0.9});
  const SurfaceCropSource dense = SurfaceCropSource::FromMesh(mesh, CropOptions{.pixel_m = 0.002});
  const PointCloud scene = Transform(T_camera_model, dense.Crop(T_camera_model).points_model);
  const KdTree tree(scene);
  const AcquisitionOptions options;
  const std::vector<ModelCrop> crops = MakeViewSphereCrops(source, options);
  ASSERT_EQ(crops.size(), 30u);
  AcquisitionOptions with_rolls = options;
  with_rolls.roll_steps = 4;
  const AcquisitionResult r = Acquire(scene, tree, source, crops, with_rolls, AlignmentOptions{});
  ASSERT_TRUE(r.acquired) << r.reason;
  EXPECT_EQ(r.hypotheses.size(), 120u);
  // The box has 180-degree symmetries: compare the visible geometry, not the rotation itself.
  const AlignmentScore exact = ScoreAlignment(source.Crop(T_camera_model).points_model, T_camera_model, tree, {});
  EXPECT_GT(r.score, 0.95);
  EXPECT_GT(exact.score, 0.95);
  EXPECT_LT(TranslationDistanceM(r.T_camera_model, T_camera_model), 0.005);
}

}  // namespace
}  // namespace mocap
