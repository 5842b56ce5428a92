#include "validate/icp.h"
#include "validate/kdtree.h"

#include <gtest/gtest.h>

#include <cstdio>

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
  const PointGrid scene(Transform(T_scene_model, BoxSurface({0.16, 0.06, 0.21}, 0.0015)));
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
  const PointGrid scene(testing::AddNoise(Transform(T_scene_model, model), rng, 0.0015));
  IcpOptions coarse;
  coarse.source_stride = 4;
  const Rigid3d start = T_scene_model * RandomPerturbation(rng, 0.015, 8.0);
  const IcpResult r = AlignPointToPoint(model, scene, start, coarse);
  EXPECT_LT(TranslationDistanceM(r.T_target_source, T_scene_model), 1e-3);
  EXPECT_LT(RotationDistanceDeg(r.T_target_source, T_scene_model), 0.5);
  EXPECT_NEAR(r.inlier_rmse_m, 0.0015 * std::sqrt(3.0), 1e-3);
}

TEST(KdTree, NearestFromAGuessFindsTheNearest) {
  std::mt19937 rng(5);
  const PointCloud cloud = testing::AddNoise(BoxSurface({0.1, 0.2, 0.3}, 0.004), rng, 0.001);
  const KdTree tree(cloud);
  std::uniform_int_distribution<size_t> any(0, tree.size() - 1);
  int compared = 0;
  for (const auto& p : testing::AddNoise(cloud, rng, 0.004)) {
    size_t plain = 0, from = any(rng) % 3 == 0 ? KdTree::kNoHint : any(rng);
    double d2_plain = 0, d2_from = 0;
    const bool found = tree.Nearest(p, 0.01, &plain, &d2_plain);
    ASSERT_EQ(tree.NearestFrom(p, 0.01, &from, &d2_from), found);
    if (!found) continue;
    EXPECT_FLOAT_EQ(d2_from, d2_plain);  // the same distance (an equidistant point may win instead)
    EXPECT_LT(d2_from, 1e-4);
    ++compared;
  }
  EXPECT_GT(compared, 1000);
}

TEST(Icp, AccelerationReachesTheSameOptimumInFewerIterations) {
  // Three faces of a long box, one of them a small end face: the registration slides slowly along the
  // box's long axis, the case Besl & McKay's extrapolation is for.
  std::mt19937 rng(4);
  const auto visible = [](const PointCloud& box) {
    PointCloud faces;
    for (const auto& p : box)
      if (p.y() > 0.0299 || p.z() > 0.0399 || p.x() > 0.1499) faces.push_back(p);
    return faces;
  };
  const PointCloud model = visible(BoxSurface({0.3, 0.06, 0.08}, 0.004));
  const Rigid3d T_scene_model = Rigid3d::FromRvec({0.2, 0.1, -0.3}, {0.05, 0.0, 0.8});
  // The scene denser than the model, as in ConvergesFromKnownOffsetsOnANoiselessBox.
  const PointGrid scene(testing::AddNoise(Transform(T_scene_model, visible(BoxSurface({0.3, 0.06, 0.08}, 0.0015))), rng, 0.0005));
  IcpOptions plain;
  plain.initial_correspondence_distance_m = plain.max_correspondence_distance_m = 0.02;
  plain.max_iterations = 300;
  plain.translation_epsilon_m = 2e-6;
  plain.rotation_epsilon_deg = 0.001;
  IcpOptions accelerated = plain;
  accelerated.accelerate = true;
  const Rigid3d start = T_scene_model * Rigid3d::FromRvec({0.0, 0.0, 0.0}, {0.006, 0.002, 0.0});
  const IcpResult a = AlignPointToPoint(model, scene, start, plain);
  const IcpResult b = AlignPointToPoint(model, scene, start, accelerated);
  ASSERT_TRUE(a.converged && b.converged);
  EXPECT_LT(TranslationDistanceM(b.T_target_source, a.T_target_source), 2e-4);
  EXPECT_LT(RotationDistanceDeg(b.T_target_source, a.T_target_source), 0.02);
  EXPECT_LT(TranslationDistanceM(b.T_target_source, T_scene_model), 5e-4);
  EXPECT_LT(b.iterations * 3, a.iterations * 2) << b.iterations << " vs " << a.iterations;
  std::printf("[icp acceleration] %d iterations plain, %d accelerated\n", a.iterations, b.iterations);
}

TEST(Icp, ReportsEmptyInputAndTooFewCorrespondences) {
  const PointCloud model = BoxSurface({0.1, 0.1, 0.1}, 0.01);
  const PointGrid empty_scene(PointCloud{});
  IcpResult r = AlignPointToPoint(model, empty_scene, Rigid3d::Identity(), IcpOptions{});
  EXPECT_EQ(r.reason, IcpStopReason::kEmptyInput);
  EXPECT_FALSE(r.converged);

  // A scene a metre away: nothing inside the gate.
  const PointGrid far_scene(Transform(Rigid3d::FromRvec({0, 0, 0}, {1, 0, 0}), model));
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
  o = IcpOptions{};
  o.acceleration_max_factor = 0.5;
  EXPECT_THROW(o.check(), InputError);
  o = IcpOptions{};
  o.acceleration_angle_deg = 90;
  EXPECT_THROW(o.check(), InputError);
  EXPECT_NO_THROW(IcpOptions{}.check());
}

}  // namespace
}  // namespace mocap
