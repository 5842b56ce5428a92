#include "core/rigid3.h"

#include <gtest/gtest.h>

#include <numbers>
#include <opencv2/calib3d.hpp>
#include <random>
#include <vector>

namespace mocap {
namespace {

constexpr double kPi = std::numbers::pi;

Rigid3d RandomPose(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  std::uniform_real_distribution<double> angle(0.0, kPi);
  return Rigid3d::FromRvec(axis * angle(rng), {n(rng), n(rng), n(rng)});
}

TEST(Rigid3, ComposesAsNamedByFrames) {
  // T_a_c = T_a_b * T_b_c: a point at the origin of c lands at T_a_b applied to T_b_c's translation.
  const Rigid3d T_a_b = Rigid3d::FromRvec({0, 0, kPi / 2}, {1, 0, 0});
  const Rigid3d T_b_c = Rigid3d::FromRvec({0, 0, 0}, {1, 0, 0});
  const Eigen::Vector3d p_a = (T_a_b * T_b_c) * Eigen::Vector3d::Zero();
  EXPECT_NEAR(p_a.x(), 1.0, 1e-12);
  EXPECT_NEAR(p_a.y(), 1.0, 1e-12);
  EXPECT_NEAR(p_a.z(), 0.0, 1e-12);
}

TEST(Rigid3, InverseUndoes) {
  std::mt19937 rng(1);
  for (int i = 0; i < 50; ++i) {
    const Rigid3d T = RandomPose(rng);
    const Rigid3d I = T * T.inverse();
    EXPECT_LT(I.translation().norm(), 1e-12);
    EXPECT_LT(RotationDistanceDeg(I, Rigid3d::Identity()), 1e-6);
  }
}

TEST(Rigid3, RvecMatchesCvRodrigues) {
  std::mt19937 rng(2);
  for (int i = 0; i < 50; ++i) {
    const Rigid3d T = RandomPose(rng);
    const Eigen::Vector3d r = T.rvec();
    cv::Mat R_cv;
    cv::Rodrigues(cv::Vec3d(r.x(), r.y(), r.z()), R_cv);
    const Eigen::Matrix3d R = T.rotation_matrix();
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 3; ++col) EXPECT_NEAR(R_cv.at<double>(row, col), R(row, col), 1e-12);
    EXPECT_LE(r.norm(), kPi + 1e-12);
  }
}

TEST(Rigid3, QuaternionOrderIsExplicit) {
  // 90 degrees about z: w = cos(45deg), z = sin(45deg).
  const double c = std::cos(kPi / 4), s = std::sin(kPi / 4);
  const Rigid3d a = Rigid3d::FromQuatWxyz(c, 0, 0, s, Eigen::Vector3d::Zero());
  const Rigid3d b = Rigid3d::FromQuatXyzw(0, 0, s, c, Eigen::Vector3d::Zero());
  EXPECT_LT(RotationDistanceDeg(a, b), 1e-9);
  const Eigen::Vector3d x_rotated = a * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(x_rotated.y(), 1.0, 1e-12);
  EXPECT_NEAR(a.quat_wxyz()[0], c, 1e-12);
  EXPECT_NEAR(a.quat_wxyz()[3], s, 1e-12);
  EXPECT_NEAR(a.quat_xyzw()[3], c, 1e-12);
  // The sign is normalised to w >= 0.
  const Rigid3d neg = Rigid3d::FromQuatWxyz(-c, 0, 0, -s, Eigen::Vector3d::Zero());
  EXPECT_NEAR(neg.quat_wxyz()[0], c, 1e-12);
}

TEST(Rigid3, SlightlyNonUnitTrackerQuaternionIsNormalised) {
  const Rigid3d T = Rigid3d::FromQuatWxyz(1.0004, 0, 0, 0, Eigen::Vector3d::Zero());
  EXPECT_NEAR(T.rotation().norm(), 1.0, 1e-15);
}

TEST(Rigid3DeathTest, FarFromUnitQuaternionAborts) {
  EXPECT_DEATH(Rigid3d::FromQuatWxyz(2, 0, 0, 0, Eigen::Vector3d::Zero()), "quaternion norm");
}

TEST(Rigid3, Matrix4RoundTrip) {
  std::mt19937 rng(3);
  const Rigid3d T = RandomPose(rng);
  const Rigid3d U = Rigid3d::FromMatrix4(T.matrix4());
  EXPECT_LT(TranslationDistanceM(T, U), 1e-12);
  EXPECT_LT(RotationDistanceDeg(T, U), 1e-9);
}

TEST(Rigid3, Distances) {
  const Rigid3d a = Rigid3d::FromRvec({0, 0, 0}, {0, 0, 0});
  const Rigid3d b = Rigid3d::FromRvec({0, RadFromDeg(10), 0}, {0.003, 0.004, 0});
  EXPECT_NEAR(TranslationDistanceM(a, b), 0.005, 1e-12);
  EXPECT_NEAR(RotationDistanceDeg(a, b), 10.0, 1e-9);
  const Rigid3d c = Rigid3d::FromRvec({RadFromDeg(10), 0, 0}, {0, 0, 0});
  EXPECT_NEAR(RotationAxisDistanceDeg(b, c), 90.0, 1e-9);
}

TEST(Rigid3, RotationAxisDistanceNearHalfATurn) {
  // 179.9 deg about +z and 179.7 deg about -z (= 180.3 deg about +z) are 0.4 deg apart: same axis.
  const Rigid3d a = Rigid3d::FromRvec({0, 0, RadFromDeg(179.9)}, {0, 0, 0});
  const Rigid3d b = Rigid3d::FromRvec({0, 0, -RadFromDeg(179.7)}, {0, 0, 0});
  EXPECT_NEAR(RotationDistanceDeg(a, b), 0.4, 1e-6);
  EXPECT_NEAR(RotationAxisDistanceDeg(a, b), 0.0, 1e-6);
  EXPECT_NEAR(RotationAxisDistanceDeg(b, a), 0.0, 1e-6);
  // Far from half a turn, opposite axes stay opposite: 10 deg about +z vs 10 deg about -z.
  const Rigid3d c = Rigid3d::FromRvec({0, 0, RadFromDeg(10)}, {0, 0, 0});
  const Rigid3d d = Rigid3d::FromRvec({0, 0, -RadFromDeg(10)}, {0, 0, 0});
  EXPECT_NEAR(RotationAxisDistanceDeg(c, d), 180.0, 1e-6);
}

TEST(Rigid3, AverageIgnoresQuaternionSign) {
  const Rigid3d a = Rigid3d::FromRvec({0, 0, RadFromDeg(10)}, {0, 0, 0});
  const Rigid3d b = Rigid3d::FromRvec({0, 0, RadFromDeg(30)}, {2, 0, 0});
  const std::vector<Rigid3d> poses = {a, b};
  const Rigid3d mean = AveragePoses(poses);
  EXPECT_NEAR(mean.rvec().z(), RadFromDeg(20), 1e-9);
  EXPECT_NEAR(mean.translation().x(), 1.0, 1e-12);
  const std::vector<double> weights = {3.0, 1.0};
  EXPECT_NEAR(AveragePoses(poses, weights).translation().x(), 0.5, 1e-12);
}

TEST(Rigid3, InterpolateTakesShortArc) {
  const Rigid3d a = Rigid3d::FromRvec({0, 0, RadFromDeg(170)}, {0, 0, 0});
  const Rigid3d b = Rigid3d::FromRvec({0, 0, RadFromDeg(-170)}, {1, 0, 0});
  const Rigid3d mid = Interpolate(a, b, 0.5);
  EXPECT_NEAR(RotationDistanceDeg(mid, Rigid3d::FromRvec({0, 0, kPi}, {0, 0, 0})), 0.0, 1e-6);
  EXPECT_NEAR(mid.translation().x(), 0.5, 1e-12);
}

}  // namespace
}  // namespace mocap
