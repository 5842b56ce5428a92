#include "calibrate/pivot.h"

#include <gtest/gtest.h>

#include <random>

#include "core/check.h"
#include "synthetic.h"

namespace mocap {
namespace {

using test::ExpSO3;

const Eigen::Vector3d kTip(0.004, -0.002, 0.142);     // tip in the pointer body, m
const Eigen::Vector3d kPivot(0.31, -0.12, 1.05);      // divot in the tracker frame, m

/// The pointer pivoting about its tip by up to `max_deg` about two axes, tracked with 0.15 mm noise.
std::vector<Rigid3d> Pivoting(unsigned seed, int count, double max_deg, bool one_axis = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Rigid3d> poses;
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d w = RadFromDeg(max_deg) * Eigen::Vector3d(u(rng), one_axis ? 0.0 : u(rng), 0.3 * u(rng));
    const Eigen::Quaterniond R = ExpSO3(Eigen::Vector3d(M_PI, 0, 0)) * ExpSO3(w);
    poses.push_back(test::Noisy(Rigid3d(R, kPivot - R * kTip), rng, 0.15e-3, 0.0));
  }
  return poses;
}

TEST(Pivot, FindsTheTipAndTheDivot) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const PivotResult result = CalibratePivot(Pivoting(seed, 200, 30));
    EXPECT_LT(1e3 * (result.p_pointer_tip - kTip).norm(), 0.2) << seed;
    EXPECT_LT(1e3 * (result.p_tracker_pivot - kPivot).norm(), 0.2) << seed;
    EXPECT_NEAR(result.rms_mm, 0.15 * std::sqrt(3.0), 0.05);
    EXPECT_TRUE(result.warnings.empty());
  }
}

TEST(Pivot, TooLittleRotationSaysHowToPivot) {
  try {
    CalibratePivot(Pivoting(1, 100, 4));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tilt it about its tip in two directions"), std::string::npos) << e.what();
  }
  EXPECT_THROW(CalibratePivot(Pivoting(1, 5, 30)), InputError);
}

TEST(Pivot, PairedPointsRecoverTheMount) {
  const Rigid3d T_objbody_mesh(ExpSO3(Eigen::Vector3d(0.4, -0.2, 1.1)), Eigen::Vector3d(0.02, 0.05, -0.01));
  const std::vector<Eigen::Vector3d> p_mesh = {{0.05, 0, 0}, {0, 0.08, 0}, {0, 0, 0.12}, {-0.04, -0.03, 0.02}, {0.03, 0.03, 0.09}};
  std::mt19937 rng(2);
  std::normal_distribution<double> n(0, 0.3e-3);
  std::vector<Eigen::Vector3d> p_objbody;
  for (const Eigen::Vector3d& p : p_mesh) p_objbody.push_back(T_objbody_mesh * p + Eigen::Vector3d(n(rng), n(rng), n(rng)));
  const PairedPointResult result = RegisterPairedPoints(p_objbody, p_mesh);
  EXPECT_LT(1e3 * TranslationDistanceM(result.T_objbody_mesh, T_objbody_mesh), 0.6);
  EXPECT_LT(RotationDistanceDeg(result.T_objbody_mesh, T_objbody_mesh), 0.5);
  ASSERT_EQ(result.fre_mm.size(), 5u);
  EXPECT_GT(result.fre_rms_mm, 0.05);
  EXPECT_LT(result.fre_rms_mm, 0.8);
}

TEST(Pivot, PairedPointsRefuseCollinearOrTooFewLandmarks) {
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {0.05, 0, 0}, {0.1, 0, 0}, {0.15, 0, 0}};
  EXPECT_THROW(RegisterPairedPoints(line, line), InputError);
  const std::vector<Eigen::Vector3d> two = {{0, 0, 0}, {0.05, 0, 0}};
  EXPECT_THROW(RegisterPairedPoints(two, two), InputError);
  const std::vector<Eigen::Vector3d> three = {{0, 0, 0}, {0.05, 0, 0}, {0, 0.05, 0}};
  EXPECT_THROW(RegisterPairedPoints(three, two), InputError);
}

}  // namespace
}  // namespace mocap
