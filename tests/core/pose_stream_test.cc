#include "core/pose_stream.h"

#include <gtest/gtest.h>

#include <vector>

#include "core/check.h"

namespace mocap {
namespace {

constexpr int64_t kMs = 1'000'000;

std::vector<PoseSample> Stream() {
  // 100 Hz, moving 1 m/s along x and rotating 10 deg per sample about z; sample 3 is missing,
  // and there is a 200 ms dropout after sample 5.
  std::vector<PoseSample> s;
  for (int i = 0; i < 6; ++i)
    s.push_back({i * 10 * kMs, PoseStatus::kValid, Rigid3d::FromRvec({0, 0, RadFromDeg(10.0 * i)}, {0.01 * i, 0, 0})});
  s[3].status = PoseStatus::kMissing;
  s.push_back({250 * kMs, PoseStatus::kValid, Rigid3d::FromRvec({0, 0, 0}, {0.25, 0, 0})});
  return s;
}

TEST(PoseStream, InterpolatesLinearlyAndSlerps) {
  const auto s = Stream();
  const InterpolatedPose p = InterpolatePose(s, 5 * kMs);
  ASSERT_TRUE(p.ok()) << p.reason();
  EXPECT_NEAR(p.pose->translation().x(), 0.005, 1e-12);
  EXPECT_NEAR(p.pose->rvec().z(), RadFromDeg(5.0), 1e-12);
  EXPECT_EQ(p.gap_ns, 10 * kMs);
  EXPECT_EQ(p.before_ns, 0);
  EXPECT_EQ(p.after_ns, 10 * kMs);
}

TEST(PoseStream, ExactHitReturnsTheSample) {
  const auto s = Stream();
  const InterpolatedPose p = InterpolatePose(s, 20 * kMs);
  ASSERT_TRUE(p.ok());
  EXPECT_EQ(p.gap_ns, 0);
  EXPECT_NEAR(p.pose->translation().x(), 0.02, 1e-15);
}

TEST(PoseStream, RefusesNextToAMissingSample) {
  const auto s = Stream();
  const InterpolatedPose p = InterpolatePose(s, 25 * kMs);
  EXPECT_FALSE(p.ok());
  EXPECT_EQ(p.failure, InterpolationFailure::kNeighbourInvalid);
  EXPECT_EQ(p.neighbour_status, PoseStatus::kMissing);
  EXPECT_NE(p.reason().find("missing"), std::string::npos);
}

TEST(PoseStream, RefusesInsideALongGap) {
  const auto s = Stream();
  const InterpolatedPose p = InterpolatePose(s, 100 * kMs);
  EXPECT_EQ(p.failure, InterpolationFailure::kGapTooLong);
  EXPECT_EQ(p.gap_ns, 200 * kMs);
  EXPECT_NE(p.reason().find("200 ms"), std::string::npos) << p.reason();
  InterpolationOptions wide;
  wide.max_gap_ns = 300 * kMs;
  EXPECT_TRUE(InterpolatePose(s, 100 * kMs, wide).ok());
}

TEST(PoseStream, RefusesOutsideTheStream) {
  const auto s = Stream();
  EXPECT_EQ(InterpolatePose(s, -1).failure, InterpolationFailure::kBeforeStart);
  EXPECT_EQ(InterpolatePose(s, 251 * kMs).failure, InterpolationFailure::kAfterEnd);
  EXPECT_EQ(InterpolatePose({}, 0).failure, InterpolationFailure::kEmptyStream);
  InterpolationOptions snap;
  snap.max_extrapolation_ns = 2 * kMs;
  EXPECT_TRUE(InterpolatePose(s, 251 * kMs, snap).ok());
  EXPECT_TRUE(InterpolatePose(s, -1 * kMs, snap).ok());
}

TEST(PoseStream, StatusNamesRoundTrip) {
  for (auto st : {PoseStatus::kValid, PoseStatus::kMissing, PoseStatus::kDisabled, PoseStatus::kOutOfVolume,
                  PoseStatus::kPartiallyInVolume})
    EXPECT_EQ(PoseStatusFromString(ToString(st)), st);
  EXPECT_THROW(PoseStatusFromString("lost"), InputError);
}

TEST(PoseStream, OptionsCheck) {
  InterpolationOptions bad;
  bad.max_gap_ns = 0;
  EXPECT_THROW(bad.check(), InputError);
}

}  // namespace
}  // namespace mocap
