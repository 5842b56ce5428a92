#include "validate/icp.h"

#include <gtest/gtest.h>

#include "synthetic.h"

namespace mocap {
namespace {

using testing::BoxSurface;
using testing::RandomPerturbation;

TEST(Kabsch, RecoversAKnownTransformExactly) {
  std::mt19937 rng(1);
  const PointCloud source = BoxSurface({0.1, 0.2, 0.3}, 0.05);
  const Rigid3d T = RandomPerturbation(rng, 0.3, 70.0);
  const Rigid3d estimate = KabschTransform(source, Transform(T, source));
  EXPECT_LT(TranslationDistanceM(estimate, T), 1e-12);
  EXPECT_LT(RotationDistanceDeg(estimate, T), 1e-9);
}

TEST(Icp, ConvergesFromKnownOffsetsOnANoiselessBox) {
  std::mt19937 rng(2);
  const PointCloud model = BoxSurface({0.16, 0.06, 0.21}, 0.004);
  const Rigid3d T_scene_model = Rigid3d::FromRvec({0.3, -0.2, 0.1}, {0.1, -0.05, 0.9});
  // The scene is sampled more densely than the model, as a camera sees a surface the model samples.
  const KdTree scene(Transform(T_scene_model, BoxSurface({0.16, 0.06, 0.21}, 0.0015)));
  for (int trial = 0; trial < 10; ++trial) {
    const Rigid3d start = T_scene_model * RandomPerturbation(rng, 0.02, 10.0);
    const IcpResult r = AlignPointToPoint(model, scene, start, IcpOptions{});
    EXPECT_TRUE(r.converged) << ToString(r.reason);
    EXPECT_LT(TranslationDistanceM(r.T_target_source, T_scene_model), 5e-4) << trial;  // a third of the scene spacing
    EXPECT_LT(RotationDistanceDeg(r.T_target_source, T_scene_model), 0.2) << trial;
    EXPECT_GT(r.fitness, 0.99);
    EXPECT_LT(r.inlier_rmse_m, 0.75e-3);  // half the scene spacing
  }
}

TEST(Icp, CoarseToFineMatchesFullAccuracyWithNoise) {
  std::mt19937 rng(3);
  const PointCloud model = BoxSurface({0.16, 0.06, 0.21}, 0.004);
  const Rigid3d T_scene_model = Rigid3d::FromRvec({0.0, 0.4, 0.0}, {0.0, 0.0, 1.0});
  const KdTree scene(testing::AddNoise(Transform(T_scene_model, model), rng, 0.0015));
  IcpOptions coarse;
  coarse.source_stride = 4;
  const Rigid3d start = T_scene_model * RandomPerturbation(rng, 0.015, 8.0);
  const IcpResult r = AlignPointToPoint(model, scene, start, coarse);
  EXPECT_LT(TranslationDistanceM(r.T_target_source, T_scene_model), 1e-3);
  EXPECT_LT(RotationDistanceDeg(r.T_target_source, T_scene_model), 0.5);
  EXPECT_NEAR(r.inlier_rmse_m, 0.0015 * std::sqrt(3.0), 1e-3);
}

TEST(Icp, ReportsEmptyInputAndTooFewCorrespondences) {
  const PointCloud model = BoxSurface({0.1, 0.1, 0.1}, 0.01);
  const KdTree empty_scene(PointCloud{});
  IcpResult r = AlignPointToPoint(model, empty_scene, Rigid3d::Identity(), IcpOptions{});
  EXPECT_EQ(r.reason, IcpStopReason::kEmptyInput);
  EXPECT_FALSE(r.converged);

  // A scene a metre away: nothing inside the gate.
  const KdTree far_scene(Transform(Rigid3d::FromRvec({0, 0, 0}, {1, 0, 0}), model));
  r = AlignPointToPoint(model, far_scene, Rigid3d::Identity(), IcpOptions{});
  EXPECT_EQ(r.reason, IcpStopReason::kTooFewCorrespondences);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_LT(TranslationDistanceM(r.T_target_source, Rigid3d::Identity()), 1e-15);
}

TEST(Icp, OptionsCheckRejectsNonsense) {
  IcpOptions o;
  o.max_correspondence_distance_m = -1;
  EXPECT_THROW(o.check(), InputError);
  o = IcpOptions{};
  o.initial_correspondence_distance_m = 0.001;
  EXPECT_THROW(o.check(), InputError);
  o = IcpOptions{};
  o.source_stride = 0;
  EXPECT_THROW(o.check(), InputError);
  EXPECT_NO_THROW(IcpOptions{}.check());
}

}  // namespace
}  // namespace mocap
