#include "validate/pose_filter.h"

#include <gtest/gtest.h>

#include <cmath>

#include "synthetic.h"

namespace mocap {
namespace {

constexpr int64_t kFrameNs = 33'333'333;  // 30 Hz

/// Ground truth: constant linear velocity and constant rotation rate about a fixed world axis.
Rigid3d TruePose(double t) {
  const Eigen::Vector3d v(0.10, -0.05, 0.02), w(0.0, 0.2, 0.5);
  return Rigid3d(ExpSO3(w * t) * Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX())),
                 Eigen::Vector3d(0.2, 0.1, 1.0) + v * t);
}

Rigid3d Noisy(const Rigid3d& T, std::mt19937& rng, double sigma_m, double sigma_deg) {
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Vector3d dr = RadFromDeg(sigma_deg) * Eigen::Vector3d(n(rng), n(rng), n(rng));
  const Eigen::Vector3d dt = sigma_m * Eigen::Vector3d(n(rng), n(rng), n(rng));
  return Rigid3d(ExpSO3(dr) * T.rotation(), T.translation() + dt);
}

/// A smooth trajectory: low process noise, so the filter averages over many frames.
PoseFilterOptions Smooth() {
  PoseFilterOptions o;
  o.accel_sigma_mps2 = 0.05;
  o.angular_accel_sigma_radps2 = 0.2;
  return o;
}

TEST(SO3, ExpLogRoundTrip) {
  const Eigen::Vector3d r(0.3, -1.2, 2.0);
  EXPECT_LT((LogSO3(ExpSO3(r)) - r).norm(), 1e-12);
  EXPECT_LT(LogSO3(Eigen::Quaterniond::Identity()).norm(), 1e-15);
}

TEST(PoseFilter, TracksAConstantVelocityTrajectoryBetterThanItsMeasurements) {
  std::mt19937 rng(5);
  PoseFilter filter(Smooth());
  filter.Initialize(Noisy(TruePose(0), rng, 0.002, 1.0), 0, 1.0);
  double raw_sq = 0, filtered_sq = 0, raw_rot_sq = 0, filtered_rot_sq = 0;
  int counted = 0;
  for (int k = 1; k <= 90; ++k) {
    const double t = k * kFrameNs * 1e-9;
    filter.Predict(k * kFrameNs);
    const Rigid3d measured = Noisy(TruePose(t), rng, 0.002, 1.0);
    ASSERT_TRUE(filter.Update(measured, 1.0).accepted) << "frame " << k;
    if (k > 45) {
      raw_sq += std::pow(TranslationDistanceM(measured, TruePose(t)), 2);
      filtered_sq += std::pow(TranslationDistanceM(filter.pose(), TruePose(t)), 2);
      raw_rot_sq += std::pow(RotationDistanceDeg(measured, TruePose(t)), 2);
      filtered_rot_sq += std::pow(RotationDistanceDeg(filter.pose(), TruePose(t)), 2);
      ++counted;
    }
  }
  EXPECT_LT(filtered_sq, 0.6 * raw_sq);
  EXPECT_LT(filtered_rot_sq, 0.6 * raw_rot_sq);
  EXPECT_LT((filter.velocity_mps() - Eigen::Vector3d(0.10, -0.05, 0.02)).norm(), 0.03);
  EXPECT_LT((filter.angular_velocity_radps() - Eigen::Vector3d(0.0, 0.2, 0.5)).norm(), 0.15);
  std::printf("[filter] RMS position %.2f mm filtered vs %.2f mm measured; rotation %.2f vs %.2f deg\n",
              1e3 * std::sqrt(filtered_sq / counted), 1e3 * std::sqrt(raw_sq / counted),
              std::sqrt(filtered_rot_sq / counted), std::sqrt(raw_rot_sq / counted));
}

TEST(PoseFilter, PropagatesThroughAnOcclusionAndGatesOutliers) {
  std::mt19937 rng(6);
  PoseFilter filter(Smooth());
  filter.Initialize(TruePose(0), 0, 1.0);
  int k = 1;
  for (; k <= 60; ++k) {
    filter.Predict(k * kFrameNs);
    filter.Update(Noisy(TruePose(k * kFrameNs * 1e-9), rng, 0.002, 1.0), 1.0);
  }
  // 10 frames (a third of a second) without measurements: constant-velocity prediction.
  const double sigma_before = filter.position_sigma_m();
  for (; k <= 70; ++k) filter.Predict(k * kFrameNs);
  EXPECT_GT(filter.position_sigma_m(), sigma_before);
  EXPECT_FALSE(filter.lost());
  EXPECT_LT(TranslationDistanceM(filter.pose(), TruePose(70 * kFrameNs * 1e-9)), 0.01);
  EXPECT_LT(RotationDistanceDeg(filter.pose(), TruePose(70 * kFrameNs * 1e-9)), 3.0);
  // A measurement 10 cm off is an outlier: rejected, state untouched.
  const Rigid3d before = filter.pose();
  const Rigid3d outlier = Rigid3d::FromRvec({0, 0, 0}, {0.1, 0, 0}) * TruePose(70 * kFrameNs * 1e-9);
  const FilterUpdate u = filter.Update(outlier, 1.0);
  EXPECT_FALSE(u.accepted);
  EXPECT_GT(u.mahalanobis_sq, 22.46);
  EXPECT_LT(TranslationDistanceM(filter.pose(), before), 1e-12);
}

TEST(PoseFilter, LowScoresWeighLess) {
  // Same innovation, two scores: the low-score update moves the state less.
  PoseFilter a, b;
  a.Initialize(Rigid3d::Identity(), 0, 1.0);
  b.Initialize(Rigid3d::Identity(), 0, 1.0);
  const Rigid3d measured = Rigid3d::FromRvec({0, 0, 0}, {0.002, 0, 0});
  a.Update(measured, 1.0);
  b.Update(measured, 0.6);
  EXPECT_GT(a.pose().translation().x(), b.pose().translation().x());
  EXPECT_GT(b.pose().translation().x(), 0.0);
}

TEST(PoseFilter, LosesTheTrackAfterALongOcclusion) {
  PoseFilter filter;
  filter.Initialize(Rigid3d::Identity(), 0, 1.0);
  filter.Predict(5'000'000'000);  // 5 s with no measurement
  EXPECT_TRUE(filter.lost());
  PoseFilterOptions bad;
  bad.gate_chi2 = 0;
  EXPECT_THROW(PoseFilter{bad}, InputError);
}

}  // namespace
}  // namespace mocap
