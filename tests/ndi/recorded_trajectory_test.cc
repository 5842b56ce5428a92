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

// BX through the protocol: INIT, TSTART at caller time `tstart_s`, BX at `bx_s`.
EmulatorReply BxAfterTstart(EmulatedTracker& tracker, double tstart_s, double bx_s) {
  tracker.Handle(FrameCommand("INIT:"), 0);
  tracker.Handle(FrameCommand("PINIT:01"), 0);
  tracker.Handle(FrameCommand("PENA:01D"), 0);
  tracker.Handle(FrameCommand("TSTART:"), tstart_s);
  return tracker.Handle(FrameCommand("BX:0801"), bx_s);
}

HandleReport OnlyHandle(const EmulatorReply& reply) {
  EXPECT_TRUE(reply.tracking_data);
  EXPECT_EQ(reply.served.handles.size(), 1u);
  return reply.served.handles.empty() ? HandleReport{} : reply.served.handles.front();
}

// `mocaplabel ndi-emulator --replay`: a client that connects 15 s after the emulator started still hears
// the recording from its start (before: tracking time was the emulator's, every body MISSING).
TEST(RecordedTrajectory, ClockFromTstartPlaysTheRecordingFromTheClientsTstart) {
  auto trajectory = std::make_shared<RecordedTrajectory>(Example(0));
  EmulatedTracker tracker({.rate_hz = 100, .clock_from_tstart = true}, trajectory);
  const EmulatorReply reply = BxAfterTstart(tracker, 15.0, 15.1125);
  const HandleReport h = OnlyHandle(reply);
  EXPECT_EQ(h.frame_number, 1011u) << "frame numbers count from TSTART";
  ASSERT_EQ(h.status, HandleStatus::kValid);
  EXPECT_NEAR(h.t_mm[0], 110.0, 1e-6);
  EXPECT_FALSE(reply.past_end);
  EXPECT_DOUBLE_EQ(tracker.TrackingTime(15.5), 0.5);

  EmulatedTracker emulator_clock({.rate_hz = 100}, trajectory);  // in process: the caller's clock as is
  EXPECT_EQ(OnlyHandle(BxAfterTstart(emulator_clock, 15.0, 15.1125)).status, HandleStatus::kMissing);
}

// The emulator's connections share the clock: a client that loses its connection and comes back
// (INIT, TSTART, no TSTOP) continues it, frame numbers go on; after a TSTOP the next TSTART starts at 0.
TEST(RecordedTrajectory, TrackingClockContinuesOverAReconnectAndRestartsAfterTstop) {
  auto trajectory = std::make_shared<ScriptedTrajectory>(DefaultTrajectoryScript(1));
  auto clock = std::make_shared<TrackingClock>();
  EmulatedTracker first({.rate_hz = 100, .clock_from_tstart = true}, trajectory, clock);
  EXPECT_EQ(OnlyHandle(BxAfterTstart(first, 10.0, 10.5)).frame_number, 1050u);
  EmulatedTracker again({.rate_hz = 100, .clock_from_tstart = true}, trajectory, clock);  // a reconnect
  EXPECT_EQ(OnlyHandle(BxAfterTstart(again, 12.0, 12.05)).frame_number, 1205u) << "the clock went on";
  again.Handle(FrameCommand("TSTOP:"), 13.0);
  EXPECT_DOUBLE_EQ(clock->Since(14.0), 0.0) << "stopped";
  again.Handle(FrameCommand("TSTART:"), 20.0);
  EXPECT_EQ(OnlyHandle(again.Handle(FrameCommand("BX:0801"), 20.1)).frame_number, 1010u) << "restarted by TSTART";
}

TEST(RecordedTrajectory, RepliesPastTheRecordingsEndAreFlagged) {
  auto trajectory = std::make_shared<RecordedTrajectory>(Example(0));
  ASSERT_TRUE(trajectory->end_s());
  EXPECT_NEAR(*trajectory->end_s(), 0.220, 1e-12);
  EmulatedTracker tracker({.rate_hz = 100, .clock_from_tstart = true}, trajectory);
  EXPECT_FALSE(BxAfterTstart(tracker, 1.0, 1.2).past_end);
  const EmulatorReply after = tracker.Handle(FrameCommand("BX:0801"), 1.25);
  EXPECT_TRUE(after.past_end);
  EXPECT_EQ(OnlyHandle(after).status, HandleStatus::kMissing);
  EXPECT_FALSE(ScriptedTrajectory(DefaultTrajectoryScript(1)).end_s()) << "a script never ends";
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
