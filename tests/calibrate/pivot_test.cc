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

TEST(Pivot, PosesPuttingThePointerInTheDivotAreDropped) {
  std::vector<Rigid3d> poses = Pivoting(5, 200, 30);
  // The pointer lowered into the divot: upright, its tip coming down from 5 cm above.
  for (int i = 0; i < 30; ++i)
    poses.insert(poses.begin(), Rigid3d(poses.front().rotation(), poses.front().translation() + Eigen::Vector3d(0, 0, 0.05 - i * 0.0016)));
  const PivotResult result = CalibratePivot(poses);
  EXPECT_LT(1e3 * (result.p_pointer_tip - kTip).norm(), 0.25);
  EXPECT_GE(result.samples_dropped, 25);
  EXPECT_LE(result.samples_dropped, 30);
  EXPECT_EQ(result.samples_used + result.samples_dropped, 230);
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

/// A tip moving between `rests` (1 s still each, 0.8 s of minimum-jerk travel between) at 60 Hz with
/// 0.15 mm noise, in the object body's frame.
void Touching(const std::vector<Eigen::Vector3d>& rests, std::vector<int64_t>& stamps, std::vector<Eigen::Vector3d>& tips) {
  std::mt19937 rng(4);
  std::normal_distribution<double> n(0, 0.15e-3);
  const int64_t step_ns = 16'666'667;
  Eigen::Vector3d from(0.3, 0.3, 0.3);
  int64_t t = 0;
  for (const Eigen::Vector3d& rest : rests) {
    for (int i = 0; i < 48; ++i, t += step_ns) {  // travel
      const double s = i / 48.0, blend = s * s * s * (10 - 15 * s + 6 * s * s);
      stamps.push_back(t), tips.push_back(from + blend * (rest - from) + Eigen::Vector3d(n(rng), n(rng), n(rng)));
    }
    for (int i = 0; i < 60; ++i, t += step_ns) stamps.push_back(t), tips.push_back(rest + Eigen::Vector3d(n(rng), n(rng), n(rng)));
    from = rest;
  }
}

TEST(Pivot, TouchesAreTheTipsRestsInOrder) {
  const std::vector<Eigen::Vector3d> rests = {{0.05, 0, 0}, {0, 0.08, 0}, {0, 0, 0.12}, {0.0504, 0, 0}};
  std::vector<int64_t> stamps;
  std::vector<Eigen::Vector3d> tips;
  Touching(rests, stamps, tips);
  const std::vector<Touch> touches = FindTouches(stamps, tips);
  ASSERT_EQ(touches.size(), rests.size());
  for (size_t i = 0; i < rests.size(); ++i) {
    EXPECT_LT(1e3 * (touches[i].p_objbody - rests[i]).norm(), 0.15) << i;
    EXPECT_GT(touches[i].samples, 55) << i;
    EXPECT_LT(touches[i].spread_mm, 0.8) << i;  // the last millimetres of the approach count in
    if (i > 0) {
      EXPECT_GT(touches[i].start_ns, touches[i - 1].end_ns);
    }
  }
  // A rest shorter than min_still_s is passing by.
  TouchOptions longer;
  longer.min_still_s = 1.5;
  EXPECT_TRUE(FindTouches(stamps, tips, longer).empty());
  // Tracking lost early in the first rest ends it there: the part after the gap is the touch.
  std::vector<int64_t> gapped = stamps;
  for (size_t i = 48 + 15; i < gapped.size(); ++i) gapped[i] += 500'000'000;
  const std::vector<Touch> after_gap = FindTouches(gapped, tips);
  ASSERT_EQ(after_gap.size(), rests.size());
  EXPECT_EQ(after_gap[0].start_ns, gapped[48 + 15]);
  EXPECT_THROW(FindTouches(std::span<const int64_t>(stamps).first(3), tips), InputError);
  longer.still_radius_mm = 0;
  EXPECT_THROW(FindTouches(stamps, tips, longer), InputError);
}

TEST(Pivot, TheLandmarksAreTheRestsThatKeepTheirDistances) {
  const std::vector<Eigen::Vector3d> p_mesh = {{0.05, 0, 0}, {0, 0.08, 0}, {0, 0, 0.12}, {-0.04, -0.03, 0.02}};
  const Rigid3d T_objbody_mesh(ExpSO3(Eigen::Vector3d(0.4, -0.2, 1.1)), Eigen::Vector3d(0.02, 0.05, -0.01));
  // Parked before, once between (a pause to look), and after.
  std::vector<Touch> rests = {{}, {}, {}, {}, {}, {}, {}};
  rests[0].p_objbody = {0.3, 0.2, 0.0}, rests[3].p_objbody = {0.0, 0.15, 0.05}, rests[6].p_objbody = {0.3, 0.21, 0.0};
  for (int i : {1, 2, 4, 5}) rests[static_cast<size_t>(i)].p_objbody = T_objbody_mesh * p_mesh[static_cast<size_t>(i < 3 ? i - 1 : i - 2)];
  rests[4].p_objbody += Eigen::Vector3d(0.0004, 0, 0);
  const TouchMatch match = MatchTouchesToLandmarks(rests, p_mesh);
  EXPECT_EQ(match.touches, (std::vector<int>{1, 2, 4, 5}));
  EXPECT_LT(match.distance_rms_mm, 0.4);
  EXPECT_THROW(MatchTouchesToLandmarks(std::span<const Touch>(rests).first(3), p_mesh), InputError);
}

}  // namespace
}  // namespace mocap
