#include "calibrate/object_mount.h"
#include "calibrate/robust_stats.h"

#include <gtest/gtest.h>

#include <random>

#include "core/check.h"
#include "synthetic.h"

namespace mocap {
namespace {

using test::ExpSO3;

const Rigid3d kTrueMount(ExpSO3(Eigen::Vector3d(0.1, -0.3, 0.05)), Eigen::Vector3d(0.012, -0.03, 0.05));

/// Records of an object seen from many directions; the labels use `current` as the mount, SegICP sees
/// the truth with noise; every `outlier_every`-th estimate is off by 3 cm.
std::vector<LabelEstimatePair> Pairs(const Rigid3d& current, unsigned seed, int count, int outlier_every = 0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<LabelEstimatePair> pairs;
  for (int i = 0; i < count; ++i) {
    const Rigid3d T_camera_objbody(ExpSO3(Eigen::Vector3d(u(rng), u(rng), u(rng))), Eigen::Vector3d(0.1 * u(rng), 0.1 * u(rng), 0.9));
    Rigid3d estimate = test::Noisy(T_camera_objbody * kTrueMount, rng, 0.8e-3, 0.25);
    if (outlier_every > 0 && i % outlier_every == 0)
      estimate = Rigid3d(estimate.rotation(), estimate.translation() + Eigen::Vector3d(0.03, 0, 0));
    pairs.push_back({T_camera_objbody * current, estimate});
  }
  return pairs;
}

TEST(ObjectMount, RecoversTheMountFromAWrongOne) {
  const Rigid3d current = kTrueMount * Rigid3d(ExpSO3(RadFromDeg(5) * Eigen::Vector3d::UnitZ()), Eigen::Vector3d(0.01, 0, 0));
  for (unsigned seed : {1u, 2u, 3u}) {
    const ObjectMountResult result = EstimateObjectMount(Pairs(current, seed, 120), current);
    EXPECT_LT(1e3 * TranslationDistanceM(result.T_objbody_mesh, kTrueMount), 0.4) << seed;
    EXPECT_LT(RotationDistanceDeg(result.T_objbody_mesh, kTrueMount), 0.1) << seed;
    EXPECT_NEAR(1e3 * result.correction.translation().norm(), 10.0, 0.5);
    EXPECT_EQ(result.records_used, 120);
    EXPECT_NEAR(result.spread_mm, 0.8 * std::sqrt(3.0), 0.3);
    EXPECT_GT(result.ci95_mm, 0.05);
    EXPECT_LT(result.ci95_mm, 0.5);
  }
}

TEST(ObjectMount, DropsEstimatesThatDisagree) {
  const ObjectMountResult result = EstimateObjectMount(Pairs(kTrueMount, 7, 100, 10), kTrueMount);
  EXPECT_EQ(result.records_dropped, 10);
  EXPECT_LT(1e3 * TranslationDistanceM(result.T_objbody_mesh, kTrueMount), 0.4);
  EXPECT_TRUE(result.warnings.empty());
  const ObjectMountResult many = EstimateObjectMount(Pairs(kTrueMount, 7, 100, 3), kTrueMount);
  EXPECT_EQ(many.records_dropped, 34);
  EXPECT_LT(1e3 * TranslationDistanceM(many.T_objbody_mesh, kTrueMount), 0.5);
  ASSERT_EQ(many.warnings.size(), 1u);
  EXPECT_NE(many.warnings[0].find("34 of 100 records disagree"), std::string::npos) << many.warnings[0];
}

TEST(ObjectMount, TooFewRecordsIsAnErrorSayingWhatToDo) {
  try {
    EstimateObjectMount(Pairs(kTrueMount, 1, 4), kTrueMount);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("too few records: 4 reliable (need 10)"), std::string::npos) << e.what();
  }
}

TEST(ObjectMount, MeanIntervalWidensForCorrelatedValues) {
  std::vector<double> independent, correlated;
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0, 1);
  double ar = 0;
  for (int i = 0; i < 2000; ++i) {
    independent.push_back(n(rng));
    ar = 0.8 * ar + 0.6 * n(rng);
    correlated.push_back(ar);
  }
  double rho_i = 0, rho_c = 0;
  const double ci_i = MeanInterval95(independent, rho_i), ci_c = MeanInterval95(correlated, rho_c);
  EXPECT_NEAR(ci_i, 1.96 / std::sqrt(2000.0), 0.01);
  EXPECT_LT(rho_i, 0.05);
  EXPECT_NEAR(rho_c, 0.8, 0.05);
  EXPECT_NEAR(ci_c, 1.96 / std::sqrt(2000.0) * 3.0, 0.02);  // sqrt(1.8 / 0.2) = 3
}

}  // namespace
}  // namespace mocap
