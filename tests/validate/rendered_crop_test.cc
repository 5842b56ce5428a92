// The renderer-backed crops against the CPU z-buffer crops: the same visible side of the same mesh, at the
// same resolution, and every rendered point on the model surface.
#include "validate/rendered_crop.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "validate/acquisition.h"
#include "validate/kdtree.h"

namespace mocap {
namespace {

const std::filesystem::path kModels = std::filesystem::path(MOCAP_SHARED_DIR) / "realdata/bop_lmo_scene2/models";

/// Fraction of `points` with a point of `tree` within `radius_m`.
double CoveredFraction(const PointCloud& points, const KdTree& tree, double radius_m) {
  int covered = 0;
  size_t index = 0;
  double distance_sq = 0;
  for (const auto& p : points) covered += tree.Nearest(p, radius_m, &index, &distance_sq);
  return points.empty() ? 0.0 : static_cast<double>(covered) / points.size();
}

class RenderedCropTest : public ::testing::TestWithParam<const char*> {};

TEST_P(RenderedCropTest, MatchesTheSurfaceCrops) {
  const Mesh mesh = LoadMesh((kModels / GetParam()).string(), 0.001);
  const CropOptions options;
  const RenderedCropSource rendered(mesh, options);
  const SurfaceCropSource surface = SurfaceCropSource::FromMesh(ToTriangleMesh(mesh), options);
  // Dense surface samples: the distance of a rendered point to the surface.
  const PointCloud dense = SampleSurface(ToTriangleMesh(mesh), 0.001);
  const KdTree dense_tree(dense);
  const std::vector<Rigid3d> views = ViewSpherePoses(6, -60, 60, Eigen::Vector3d::Zero(), 0.8);
  for (size_t i = 0; i < views.size(); ++i) {
    // Off the optical axis too, as crops at a label's pose are.
    const Rigid3d T_camera_model = Rigid3d::FromRvec({0, 0, 0}, {0.15, -0.1, 0.0}) * views[i];
    const ModelCrop a = rendered.Crop(T_camera_model), b = surface.Crop(T_camera_model);
    ASSERT_GT(a.points_model.size(), 100u) << i;
    const double ratio = static_cast<double>(a.points_model.size()) / b.points_model.size();
    EXPECT_NEAR(ratio, 1.0, 0.25) << "view " << i;
    EXPECT_GT(CoveredFraction(a.points_model, dense_tree, 0.001), 0.99) << "view " << i;
    const KdTree ta(a.points_model), tb(b.points_model);
    EXPECT_GT(CoveredFraction(a.points_model, tb, 0.006), 0.95) << "view " << i;  // one crop pixel and a bit
    EXPECT_GT(CoveredFraction(b.points_model, ta, 0.006), 0.95) << "view " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(LmoMeshes, RenderedCropTest, ::testing::Values("obj_000001.ply", "obj_000009.ply"));

TEST(RenderedCrop, ParallelCallsAgreeWithSerialOnes) {
  const Mesh mesh = LoadMesh((kModels / "obj_000005.ply").string(), 0.001);
  const RenderedCropSource rendered(mesh, CropOptions{});
  AcquisitionOptions options;
  const std::vector<ModelCrop> parallel = MakeViewSphereCrops(rendered, options);  // OpenMP inside
  for (int i = 0; i < options.num_crops; i += 7)
    EXPECT_EQ(rendered.Crop(parallel[i].T_camera_model).points_model, parallel[i].points_model) << i;
}

}  // namespace
}  // namespace mocap
