#include "validate/alignment_score.h"

#include <gtest/gtest.h>

#include "synthetic.h"

namespace mocap {
namespace {

TEST(AlignmentScore, CountsOnlyPointsWithinTau) {
  const PointCloud scene = {{0, 0, 1}, {0.1, 0, 1}, {0.2, 0, 1}};
  const PointGrid tree(scene);
  // Model points 5 mm, 9 mm and 15 mm from their scene points: two of three within tau = 1 cm.
  const PointCloud crop = {{0.005, 0, 1}, {0.1, 0.009, 1}, {0.2, 0, 1.015}};
  const AlignmentScore s = ScoreAlignment(crop, Rigid3d::Identity(), tree, AlignmentOptions{});
  EXPECT_EQ(s.matched, 2);
  EXPECT_EQ(s.model_points, 3);
  EXPECT_DOUBLE_EQ(s.score, 2.0 / 3.0);
}

TEST(AlignmentScore, EachScenePointIsClaimedOnce) {
  // Three model points crowd one scene point: only one may claim it (a plain nearest-neighbour inlier
  // ratio such as ICP fitness would say 1.0 here).
  const PointGrid tree(PointCloud{{0, 0, 1}});
  const PointCloud crop = {{0, 0, 1.001}, {0, 0, 1.002}, {0.001, 0, 1}};
  const AlignmentScore s = ScoreAlignment(crop, Rigid3d::Identity(), tree, AlignmentOptions{});
  EXPECT_EQ(s.matched, 1);
  EXPECT_DOUBLE_EQ(s.score, 1.0 / 3.0);
}

TEST(AlignmentScore, FallsBackToTheClosestFreeScenePointWithinTau) {
  // Scene points A (x = 0) and B (x = 8 mm). Model point 1 at 1 mm takes A; model point 2 at 2 mm also
  // has A nearest, so it takes B (6 mm away, within tau). Model point 3 finds both taken.
  const PointGrid tree(PointCloud{{0, 0, 1}, {0.008, 0, 1}});
  const PointCloud crop = {{0.001, 0, 1}, {0.002, 0, 1}, {0.0, 0.001, 1}};
  const AlignmentScore s = ScoreAlignment(crop, Rigid3d::Identity(), tree, AlignmentOptions{});
  EXPECT_EQ(s.matched, 2);
  EXPECT_EQ(s.second_choice, 1);
  // With tau = 5 mm, B is out of reach for model point 2.
  const AlignmentScore tight = ScoreAlignment(crop, Rigid3d::Identity(), tree, AlignmentOptions{.tau_m = 0.005});
  EXPECT_EQ(tight.matched, 1);
}

TEST(AlignmentScore, AppliesThePoseAndIsOneForAnExactCrop) {
  const PointCloud model = testing::BoxSurface({0.1, 0.05, 0.2}, 0.005);
  const Rigid3d T_scene_model = Rigid3d::FromRvec({0.2, 0.1, -0.3}, {0.05, 0.0, 0.8});
  const PointGrid tree(Transform(T_scene_model, model));
  EXPECT_DOUBLE_EQ(ScoreAlignment(model, T_scene_model, tree, AlignmentOptions{}).score, 1.0);
  // Turned by 30 deg about the body diagonal, points beyond about 2 cm from the centre move more than
  // tau out of their face planes. (A pure shift would let whole faces slide within their planes.)
  const Rigid3d turned = T_scene_model * Rigid3d::FromRvec(Eigen::Vector3d(1, 1, 1).normalized() * RadFromDeg(30), {0, 0, 0});
  EXPECT_LT(ScoreAlignment(model, turned, tree, AlignmentOptions{}).score, 0.5);
}

TEST(AlignmentScore, EmptyInputsScoreZero) {
  const PointGrid empty(PointCloud{});
  EXPECT_EQ(ScoreAlignment({{0, 0, 1}}, Rigid3d::Identity(), empty, AlignmentOptions{}).score, 0.0);
  const PointGrid tree(PointCloud{{0, 0, 1}});
  EXPECT_EQ(ScoreAlignment({}, Rigid3d::Identity(), tree, AlignmentOptions{}).score, 0.0);
  EXPECT_THROW(AlignmentOptions{.tau_m = 0}.check(), InputError);
}

}  // namespace
}  // namespace mocap
