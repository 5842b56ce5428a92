// RecordedTrajectory: a recorded tracker stream as the emulator's bodies (interpolation between
// samples, recorded dropouts and volume status, nothing outside the recording).
#include <gtest/gtest.h>

#include "capture/ndi/commands.h"
#include "capture/ndi/emulated_tracker.h"
#include "capture/ndi/recorded_trajectory.h"
#include "capture/ndi/reply.h"
#include "core/check.h"

namespace mocap::ndi {
namespace {

constexpr int64_t kMs = 1'000'000;

PoseSample Sample(int64_t stamp_ns, double x_m, PoseStatus status = PoseStatus::kValid) {
  return {stamp_ns, status, Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(x_m, Eigen::Vector3d::UnitZ())),
                                    Eigen::Vector3d(x_m, 0.5, -1.5))};
}

// One body moving along x at 1 m/s, sampled every 10 ms from 100 ms (recording clock), with a
// missing sample at 150 ms and an out-of-volume one at 200 ms.
RecordedTrajectory Example(int64_t origin_ns) {
  RecordedBody body{"tool", {}};
  for (int k = 0; k <= 12; ++k) {
    const int64_t t = (100 + 10 * k) * kMs;
    const PoseStatus status = k == 5 ? PoseStatus::kMissing : k == 10 ? PoseStatus::kOutOfVolume : PoseStatus::kValid;
    body.samples.push_back(Sample(t, 1e-9 * static_cast<double>(t), status));
  }
  RecordedTrajectoryOptions options;
  options.origin_ns = origin_ns;
  return RecordedTrajectory({body}, options);
}

TEST(RecordedTrajectory, InterpolatesBetweenRecordedSamplesOnItsOwnClock) {
  const RecordedTrajectory trajectory = Example(/*origin_ns=*/50 * kMs);
  ASSERT_EQ(trajectory.body_count(), 1);
  EXPECT_EQ(trajectory.body_name(0), "tool");
  // Tracking time 0.0625 s is recording time 112.5 ms: between the samples at 110 and 120 ms.
  const BodyState state = trajectory.At(0, 0.0625);
  ASSERT_FALSE(state.forced_missing);
  EXPECT_NEAR(state.T_tracker_body.translation().x(), 0.1125, 1e-9);
  EXPECT_NEAR(Eigen::AngleAxisd(state.T_tracker_body.rotation()).angle(), 0.1125, 1e-9);
  EXPECT_EQ(state.port_status_bits, 0u);
  EXPECT_EQ(trajectory.last_stamp_ns(), 220 * kMs);
}

TEST(RecordedTrajectory, ReportsRecordedDropoutsVolumeAndNothingOutsideTheRecording) {
  const RecordedTrajectory trajectory = Example(0);
  EXPECT_TRUE(trajectory.At(0, 0.099).forced_missing) << "before the first sample";
  EXPECT_TRUE(trajectory.At(0, 0.221).forced_missing) << "after the last sample";
  EXPECT_TRUE(trajectory.At(0, 0.150).forced_missing) << "the recorded missing sample";
  EXPECT_TRUE(trajectory.At(0, 0.145).forced_missing) << "nearest to the missing sample";
  const BodyState held = trajectory.At(0, 0.142);  // next to the valid 140 ms sample, 150 is missing
  ASSERT_FALSE(held.forced_missing);
  EXPECT_NEAR(held.T_tracker_body.translation().x(), 0.140, 1e-12);
  const BodyState out = trajectory.At(0, 0.201);
  ASSERT_FALSE(out.forced_missing) << "out of volume keeps its transform";
  EXPECT_EQ(out.port_status_bits, port_status::kOutOfVolume);
  EXPECT_NEAR(out.T_tracker_body.translation().x(), 0.200, 1e-12);
}

TEST(RecordedTrajectory, EmulatorServesTheRecordedPoseAndVolumeStatus) {
  auto trajectory = std::make_shared<RecordedTrajectory>(Example(0));
  EmulatedTrackerOptions options;
  options.rate_hz = 100;
  EmulatedTracker tracker(options, trajectory);
  const uint32_t frame = tracker.FrameAt(0.1125);  // frame time 0.110 s: exactly a recorded sample
  const HandleReport valid = tracker.Report(0, frame, reply_option::kTransforms | reply_option::kOutOfVolume);
  ASSERT_EQ(valid.status, HandleStatus::kValid);
  EXPECT_NEAR(valid.t_mm[0], 110.0, 1e-6);
  const HandleReport out = tracker.Report(0, tracker.FrameAt(0.2001), reply_option::kTransforms | reply_option::kOutOfVolume);
  EXPECT_TRUE(out.port_status & port_status::kOutOfVolume);
  const HandleReport hidden = tracker.Report(0, tracker.FrameAt(0.2001), reply_option::kTransforms);
  EXPECT_EQ(hidden.status, HandleStatus::kMissing) << "out of volume without reply option 0x0800 is MISSING";
}

TEST(RecordedTrajectory, RefusesUnsortedDuplicateOrNoBodies) {
  EXPECT_THROW(RecordedTrajectory({}, {}), InputError);
  RecordedBody unsorted{"a", {Sample(20 * kMs, 0), Sample(10 * kMs, 0)}};
  EXPECT_THROW(RecordedTrajectory({unsorted}, {}), InputError);
  RecordedBody a{"a", {Sample(10 * kMs, 0)}};
  EXPECT_THROW(RecordedTrajectory({a, a}, {}), InputError);
}

}  // namespace
}  // namespace mocap::ndi
