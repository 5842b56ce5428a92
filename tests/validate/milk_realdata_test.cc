// Real Kinect data: PCL's milk_cartoon_all_small_clorox.pcd scene with milk.pcd, an exact crop of the
// same scene, as the model. The true pose of the model in the scene is therefore the identity.
#include <gtest/gtest.h>

#include <cstdio>
#include <algorithm>
#include <random>

#include "pcd_reader.h"
#include "synthetic.h"
#include "validate/acquisition.h"
#include "validate/icp.h"

namespace mocap {
namespace {

const std::string kPclDir = std::string(MOCAP_SHARED_DIR) + "/realdata/pcl/";

struct MilkScene {
  PointCloud model;  ///< milk.pcd, camera frame = model frame
  PointCloud scene;  ///< scene points within 1.5 cm of the milk's box: the carton plus segmentation bleed
};

const MilkScene& Milk() {
  static const MilkScene milk = [] {
    MilkScene m;
    m.model = testing::FinitePoints(testing::ReadPcd(kPclDir + "milk.pcd").points);
    const testing::PcdCloud scene = testing::ReadPcd(kPclDir + "milk_cartoon_all_small_clorox.pcd");
    EXPECT_EQ(scene.width, 640);
    EXPECT_EQ(scene.height, 480);
    const Box3d box = BoundingBox(m.model, 0.015);
    for (const auto& p : testing::FinitePoints(scene.points))
      if (box.contains(p)) m.scene.push_back(p);
    m.scene = VoxelDownsample(m.scene, 0.003);
    return m;
  }();
  return milk;
}

/// A start up to 3 cm and 20 deg off the identity, rotated about the model centre (a rotation about
/// the camera origin would move an object a metre away by decimetres).
Rigid3d PerturbedStart(std::mt19937& rng, const Eigen::Vector3d& center) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Rigid3d delta = testing::RandomPerturbation(rng, 0.03 * unit(rng), 20.0 * unit(rng));
  const Rigid3d about_center = Rigid3d::FromRvec({0, 0, 0}, center) * Rigid3d(delta.rotation(), Eigen::Vector3d::Zero()) *
                               Rigid3d::FromRvec({0, 0, 0}, -center);
  return Rigid3d::FromRvec({0, 0, 0}, delta.translation()) * about_center;
}

TEST(MilkRealData, ModelIsAnExactCropOfTheScene) {
  const MilkScene& m = Milk();
  EXPECT_EQ(m.model.size(), 13704u);
  const PointGrid full_scene(testing::FinitePoints(testing::ReadPcd(kPclDir + "milk_cartoon_all_small_clorox.pcd").points));
  EXPECT_DOUBLE_EQ(ScoreAlignment(m.model, Rigid3d::Identity(), full_scene, AlignmentOptions{.tau_m = 1e-6}).score, 1.0);
}

TEST(MilkRealData, IcpReturnsToIdentityFrom20PerturbedStarts) {
  const MilkScene& m = Milk();
  const PointCloud model = VoxelDownsample(m.model, 0.005);
  const PointGrid tree(m.scene);
  const Eigen::Vector3d center = Centroid(m.model);
  std::mt19937 rng(7);
  double worst_mm = 0, worst_deg = 0;
  std::vector<int> iterations;
  for (int trial = 0; trial < 20; ++trial) {
    const Rigid3d start = PerturbedStart(rng, center);
    const IcpResult r = AlignPointToPoint(model, tree, start, IcpOptions{});
    iterations.push_back(r.iterations);
    const double e_mm = 1e3 * TranslationDistanceM(r.T_target_source, Rigid3d::Identity());
    const double e_deg = RotationDistanceDeg(r.T_target_source, Rigid3d::Identity());
    EXPECT_LT(e_mm, 2.0) << "trial " << trial << " " << ToString(r.reason);
    EXPECT_LT(e_deg, 1.0) << "trial " << trial;
    worst_mm = std::max(worst_mm, e_mm);
    worst_deg = std::max(worst_deg, e_deg);
  }
  std::sort(iterations.begin(), iterations.end());
  std::printf("[milk ICP] %zu model / %zu scene points, worst of 20 starts: %.3f mm, %.3f deg, iterations median %d max %d\n",
              model.size(), m.scene.size(), worst_mm, worst_deg, iterations[10], iterations.back());
}

TEST(MilkRealData, AcquisitionReturnsToIdentityFrom20PerturbedStarts) {
  const MilkScene& m = Milk();
  const SurfaceCropSource source(m.model, CropOptions{});
  const PointGrid tree(m.scene);
  const Eigen::Vector3d center = Centroid(m.model);
  std::mt19937 rng(11);
  double worst_mm = 0, worst_deg = 0, worst_score = 1;
  for (int trial = 0; trial < 20; ++trial) {
    const Rigid3d prior = PerturbedStart(rng, center);
    const AcquisitionResult r = AcquireAround(m.scene, tree, source, prior, AcquisitionOptions{}, AlignmentOptions{});
    ASSERT_GE(r.best, 0);
    EXPECT_TRUE(r.acquired) << r.reason;
    const double e_mm = 1e3 * TranslationDistanceM(r.T_camera_model, Rigid3d::Identity());
    const double e_deg = RotationDistanceDeg(r.T_camera_model, Rigid3d::Identity());
    EXPECT_LT(e_mm, 2.0) << "trial " << trial << " score " << r.score << " best " << r.best;
    EXPECT_LT(e_deg, 1.0) << "trial " << trial;
    worst_mm = std::max(worst_mm, e_mm);
    worst_deg = std::max(worst_deg, e_deg);
    worst_score = std::min(worst_score, r.score);
  }
  std::printf("[milk acquisition] 30 hypotheses per start, worst of 20 starts: %.3f mm, %.3f deg, lowest best score %.3f\n",
              worst_mm, worst_deg, worst_score);
}

}  // namespace
}  // namespace mocap
