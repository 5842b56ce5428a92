#include "validate/model_crop.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <optional>
#include <random>

#include "validate/acquisition.h"
#include "validate/frame_visibility.h"
#include "synthetic.h"

namespace mocap {
namespace {


TEST(ModelCrop, ZBufferKeepsOnlyTheFacingSide) {
  const SurfaceCropSource source = SurfaceCropSource::FromMesh(testing::BoxMesh({0.1, 0.1, 0.1}), CropOptions{});
  // Camera 1 m in front of the z = +5 cm face, looking at it straight on: only that face is visible.
  const Rigid3d T_camera_model = LookAt({0, 0, 1.0}, {0, 0, 0}, {0, 1, 0});
  const ModelCrop crop = source.Crop(T_camera_model);
  ASSERT_FALSE(crop.points_model.empty());
  for (const auto& p : crop.points_model) EXPECT_NEAR(p.z(), 0.05, 1e-9);
  // About one point per 5 mm pixel over a 10 cm face: (10 cm / 5 mm + 1)^2 = 441.
  EXPECT_NEAR(static_cast<double>(crop.points_model.size()), 441.0, 50.0);
  EXPECT_NEAR(crop.view_direction_model.z(), 1.0, 1e-9);
}


/// The crop by a plain per-pixel map (what SurfaceCropSource computed before its dense z-buffer).
PointCloud ReferenceCrop(const PointCloud& surface, const Rigid3d& T_camera_model, double pixel_m) {
  const double f = (T_camera_model * Centroid(surface)).z() / pixel_m;
  std::map<std::pair<int64_t, int64_t>, std::pair<float, size_t>> nearest;
  std::vector<std::optional<std::pair<int64_t, int64_t>>> pixel(surface.size());
  for (size_t i = 0; i < surface.size(); ++i) {
    const Eigen::Vector3d p = T_camera_model * surface[i];
    if (p.z() <= 1e-6) continue;
    const double scale = f / p.z();
    pixel[i] = {static_cast<int64_t>(std::floor(scale * p.x())), static_cast<int64_t>(std::floor(scale * p.y()))};
    auto [it, inserted] = nearest.try_emplace(*pixel[i], static_cast<float>(p.z()), i);
    if (!inserted && static_cast<float>(p.z()) < it->second.first) it->second = {static_cast<float>(p.z()), i};
  }
  PointCloud out;
  for (size_t i = 0; i < surface.size(); ++i)
    if (pixel[i] && nearest.at(*pixel[i]).second == i) out.push_back(surface[i]);
  return out;
}

TEST(ModelCrop, DenseAndSparseZBuffersMatchAPlainPerPixelMap) {
  const TriangleMesh mesh = testing::BoxMesh({0.2, 0.2, 1.0});
  const SurfaceCropSource source = SurfaceCropSource::FromMesh(mesh, CropOptions{});
  // Outside the box (dense z-buffer over the box's projection), and inside it looking down its length
  // (corners behind the camera: the sparse map).
  for (const Rigid3d& T_camera_model : {Rigid3d::FromRvec({0.4, -0.3, 0.2}, {0.02, -0.01, 1.5}),
                                        LookAt({0.0, 0.0, 0.3}, {0.0, 0.0, -0.5}, {0, 1, 0})}) {
    const PointCloud crop = source.Crop(T_camera_model).points_model;
    ASSERT_GT(crop.size(), 100u);
    EXPECT_EQ(crop, ReferenceCrop(source.surface_model(), T_camera_model, CropOptions{}.pixel_m));
  }
}

// The crops' pixel rounding stands in for std::lround: the same pixel for every coordinate an image can
// hold, halves (away from zero) and their neighbouring doubles included.
TEST(ModelCrop, NearestPixelRoundsAsLround) {
  std::vector<double> xs = {0.0, -0.0, 0.5, -0.5, 1.5, -1.5, 639.5, -0.49999999999999994, 0.49999999999999994};
  for (int k = -1000; k <= 1000; ++k) {
    const double half = k + 0.5;
    xs.insert(xs.end(), {half, std::nextafter(half, 1e9), std::nextafter(half, -1e9), static_cast<double>(k)});
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coordinate(-2000.0, 2000.0);
  for (int i = 0; i < 100000; ++i) xs.push_back(coordinate(rng));
  for (const double x : xs) ASSERT_EQ(NearestPixel(x), static_cast<int>(std::lround(x))) << x;
  EXPECT_EQ(NearestPixel(3e9), -1);
  EXPECT_EQ(NearestPixel(-1e12), -1);
  EXPECT_EQ(NearestPixel(std::nan("")), -1);
}

/// A crop source that shows every point of a cloud from anywhere.
class EveryPoint : public CropSource {
 public:
  explicit EveryPoint(PointCloud points) : points_(std::move(points)) {}
  ModelCrop Crop(const Rigid3d& T_camera_model) const override { return {points_, {}, T_camera_model, {}}; }
  const PointCloud& surface_model() const override { return points_; }

 private:
  PointCloud points_;
};

TEST(VisibleInFrame, KeepsThePointsThatProjectPlacesOnAVisiblePixel) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  PointCloud points;
  for (int i = 0; i < 4000; ++i) points.push_back({0.3 * unit(rng), 0.3 * unit(rng), 0.3 * unit(rng)});
  const EveryPoint source(points);
  DepthImage depth_m(640, 480);
  LabelImage mask(640, 480);
  for (float& d : depth_m.data) d = unit(rng) < -0.8 ? 0.0f : static_cast<float>(0.9 + 0.3 * unit(rng));
  for (uint16_t& m : mask.data) m = static_cast<uint16_t>(unit(rng) < 0 ? 1 : unit(rng) < 0 ? 2 : 0);
  PinholeCamera distorted = testing::Kinect();
  distorted.dist = {0.1, -0.05, 0.001, 0.002, 0, 0, 0, 0};
  int kept = 0, left = 0;
  for (const PinholeCamera& camera : {testing::Kinect(), distorted}) {
    const VisibleInFrameCropSource visible(source, camera, depth_m, mask, 1, 0.02);
    for (const double z_m : {1.0, 0.2}) {  // at 0.2 m some points lie behind the camera
      const Rigid3d T_camera_model(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized())),
                                   Eigen::Vector3d(0.02, -0.03, z_m));
      // The rule of frame_visibility.h, through the camera's own projection and std::lround.
      PointCloud expected;
      for (const auto& p_model : points) {
        const Eigen::Vector3d p = T_camera_model * p_model;
        const auto pixel = camera.Project(p);
        if (!pixel) continue;
        const int u = static_cast<int>(std::lround(pixel->x())), v = static_cast<int>(std::lround(pixel->y()));
        if (!depth_m.contains(u, v)) continue;
        const float d = depth_m.at(u, v);
        if (mask.at(u, v) != 0 && !(d > 0)) continue;
        if (mask.at(u, v) != 1 && d > 0 && d < p.z() - 0.02) continue;
        expected.push_back(p_model);
      }
      const PointCloud got = visible.CropPoints(T_camera_model).points_model;
      ASSERT_EQ(got.size(), expected.size());
      for (size_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i], expected[i]) << i;
      kept += static_cast<int>(got.size()), left += static_cast<int>(points.size() - got.size());
    }
  }
  EXPECT_GT(kept, 2000);  // both answers occur
  EXPECT_GT(left, 2000);
}

TEST(ModelCrop, MeshCheckRejectsBadIndices) {
  TriangleMesh mesh = testing::BoxMesh({0.1, 0.1, 0.1});
  mesh.triangles.push_back({0, 1, 99});
  EXPECT_THROW(mesh.check(), InputError);
  EXPECT_THROW(TriangleMesh{}.check(), InputError);
}

TEST(Acquisition, OptionsCheckRejectsNonsense) {
  EXPECT_NO_THROW(AcquisitionOptions{}.check());
  AcquisitionOptions o;
  o.hypothesis_stride = 0;
  EXPECT_THROW(o.check(), InputError);
  o = AcquisitionOptions{};
  o.refine_count = 0;
  EXPECT_THROW(o.check(), InputError);
  o = AcquisitionOptions{};
  o.refine_icp.acceleration_max_factor = 0;
  EXPECT_THROW(o.check(), InputError);
}

TEST(Acquisition, ViewSphereFindsABoxPoseWithoutAPrior) {
  // An elongated box (no symmetric ambiguity beyond the box's own 180-degree flips) seen by a camera.
  const TriangleMesh mesh = testing::BoxMesh({0.16, 0.06, 0.21});
  const SurfaceCropSource source = SurfaceCropSource::FromMesh(mesh, CropOptions{});
  const Rigid3d T_camera_model = Rigid3d::FromRvec({0.9, 0.3, -0.2}, {0.05, -0.02, 0.9});
  const SurfaceCropSource dense = SurfaceCropSource::FromMesh(mesh, CropOptions{.pixel_m = 0.002});
  const PointCloud scene = Transform(T_camera_model, dense.Crop(T_camera_model).points_model);
  const PointGrid tree(scene);
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
