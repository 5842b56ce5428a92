#include "calibrate/depth_to_color.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "core/check.h"
#include "synthetic.h"

namespace mocap {
namespace {

using test::ExpSO3;

// A Kinect v2-like depth camera 52 mm beside the colour camera, turned by about half a degree.
const Rigid3d kT_color_depth(ExpSO3(Eigen::Vector3d(0.004, -0.006, 0.003)), Eigen::Vector3d(0.052, 0.0012, -0.0021));

/// The board's points as the depth camera measures them: a grid over the board with noise along the
/// ray (ToF, 1.5 mm) and a tenth of the points on the wall behind.
std::vector<Eigen::Vector3d> DepthPoints(const Rigid3d& T_color_board, const BoardSpec& spec, std::mt19937& rng) {
  std::normal_distribution<double> noise(0, 0.0015);
  std::uniform_real_distribution<double> u(0, 1);
  const Rigid3d T_depth_board = kT_color_depth.inverse() * T_color_board;
  std::vector<Eigen::Vector3d> points;
  for (double x = 0.005; x < spec.squares_x * spec.square_m; x += 0.008)
    for (double y = 0.005; y < spec.squares_y * spec.square_m; y += 0.008) {
      Eigen::Vector3d p = T_depth_board * Eigen::Vector3d(x, y, 0);
      if (u(rng) < 0.1) p *= 1.3 + u(rng);  // the wall seen past the board's edge
      points.push_back(p * (1 + noise(rng) / p.norm()));
    }
  return points;
}

TEST(DepthToColor, PlanesOfTheBoardGiveTheExtrinsic) {
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937 rng(seed);
    const BoardSpec spec = test::TestBoard();
    std::vector<PlanePair> views;
    for (int i = 0; i < 20; ++i) {
      const Rigid3d T_color_board = test::RandomBoardPose(rng, test::Kinect1Camera(), spec, 0.7, 1.4, 10, 40);
      const std::optional<PlaneFit> fit = FitPlane(DepthPoints(T_color_board, spec, rng));
      ASSERT_TRUE(fit.has_value());
      EXPECT_LT(fit->rms_mm, 2.5);
      views.push_back({fit->plane, BoardPlane(T_color_board)});
    }
    const DepthToColorResult r = EstimateDepthToColor(views);
    std::printf("seed %u: %.3f mm, %.4f deg from the truth; offsets %.3f mm RMS, normals %.4f deg RMS, spread %.1f deg\n", seed,
                1e3 * TranslationDistanceM(r.T_color_depth, kT_color_depth), RotationDistanceDeg(r.T_color_depth, kT_color_depth),
                r.offset_rms_mm, r.normal_rms_deg, r.normal_spread_deg);
    EXPECT_LT(1e3 * TranslationDistanceM(r.T_color_depth, kT_color_depth), 1.0) << seed;
    EXPECT_LT(RotationDistanceDeg(r.T_color_depth, kT_color_depth), 0.1) << seed;
    EXPECT_LT(r.offset_rms_mm, 0.5);
    EXPECT_GT(r.normal_spread_deg, 10);
    EXPECT_TRUE(r.warnings.empty());
  }
}

TEST(DepthToColor, ABoardThatAlwaysFacesOneWayIsRefused) {
  std::vector<PlanePair> views;
  for (int i = 0; i < 10; ++i) {
    const Rigid3d T_color_board(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.1 * i, 0.0, 1.0 + 0.05 * i));
    const Plane color = BoardPlane(T_color_board);
    views.push_back({{kT_color_depth.rotation().inverse() * color.normal, color.offset_m - color.normal.dot(kT_color_depth.translation())}, color});
  }
  EXPECT_THROW(EstimateDepthToColor(views), InputError);
  EXPECT_THROW(EstimateDepthToColor(std::span<const PlanePair>(views).first(3)), InputError);
  EXPECT_FALSE(FitPlane(std::vector<Eigen::Vector3d>(50, Eigen::Vector3d(0, 0, 1))).has_value());
}

}  // namespace
}  // namespace mocap
