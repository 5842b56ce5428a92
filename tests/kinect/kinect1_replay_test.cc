// The Kinect1 capture path driven through libfreenect's own replay: kinect_replay_dump runs with the
// fakenect build of libfreenect over recordings made from real Kinect1 frames (TUM fr1/desk), and what it
// received is compared with what was recorded.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "capture/kinect/kinect1_depth.h"
#include "core/clock.h"
#include "subprocess.h"
#include "tum_recording.h"

namespace mocap::capture {
namespace {

namespace fs = std::filesystem;
using testing::FakenectEnv;
using testing::RunProcess;

struct Replay {
  nlohmann::json summary;
  fs::path out_dir;
};

Replay RunReplay(const fs::path& recording, const fs::path& out_dir, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> argv = {KINECT_REPLAY_DUMP, out_dir.string()};
  argv.insert(argv.end(), extra.begin(), extra.end());
  const auto result = RunProcess(argv, FakenectEnv(recording), out_dir.string() + ".log");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  std::ifstream in(out_dir / "frames.json");
  return {nlohmann::json::parse(in), out_dir};
}

// Depth delivered (mm) against the TUM depth recorded (m): exactly the fit's value of the recorded raw
// code, and within the quantisation of the 11-bit disparity at that depth plus the 0.5 mm output rounding.
void ExpectDepthMatches(const cv::Mat& depth_mm, const cv::Mat& depth_m, double* worst_error_m, double* worst_allowed_m) {
  ASSERT_EQ(depth_mm.type(), CV_16UC1);
  ASSERT_EQ(depth_mm.size(), depth_m.size());
  const Raw11ToMmTable table = Raw11ToMmTable::FromFit();
  int64_t mismatches = 0;
  for (int v = 0; v < depth_m.rows; ++v) {
    for (int u = 0; u < depth_m.cols; ++u) {
      const double z_m = depth_m.at<float>(v, u);
      const uint16_t got_mm = depth_mm.at<uint16_t>(v, u);
      if (z_m == 0.0) {
        mismatches += got_mm != 0;
        continue;
      }
      mismatches += got_mm != table[DepthMToRaw11(z_m)];
      const double error_m = std::abs(got_mm * 1e-3 - z_m);
      const double allowed_m = Raw11RoundTripErrorM(z_m) + 0.5e-3 + 1e-9;
      mismatches += error_m > allowed_m;
      if (error_m > *worst_error_m) {
        *worst_error_m = error_m;
        *worst_allowed_m = allowed_m;
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
}

void ExpectReplayMatches(const Replay& replay, const std::vector<testing::TumFrame>& frames,
                         const std::vector<testing::RecordedFrame>& recorded) {
  const auto& got = replay.summary.at("frames");
  ASSERT_EQ(got.size(), frames.size()) << replay.summary.dump(1);
  EXPECT_TRUE(replay.summary.at("stream_ended").get<bool>());
  EXPECT_EQ(replay.summary.at("depth_unpaired"), 0);
  EXPECT_EQ(replay.summary.at("color_unpaired"), 0);
  double worst_error_m = 0, worst_allowed_m = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    const auto& f = got[i];
    EXPECT_EQ(f.at("sequence"), i);
    EXPECT_EQ(f.at("depth_ticks_raw").get<uint32_t>(), static_cast<uint32_t>(recorded[i].ticks & 0xffffffffu));
    EXPECT_EQ(f.at("color_ticks_raw").get<uint32_t>(), static_cast<uint32_t>(recorded[i].ticks & 0xffffffffu));
    EXPECT_EQ(f.at("depth_ticks").get<int64_t>(), static_cast<int64_t>(recorded[i].ticks));
    EXPECT_TRUE(f.at("depth_registered").get<bool>());
    EXPECT_EQ(f.at("intrinsics_source"), "recording");
    EXPECT_DOUBLE_EQ(f.at("fx").get<double>(), 525.0);
    const std::string seq = std::to_string(i);
    const cv::Mat bgr = cv::imread((replay.out_dir / ("color_" + seq + ".png")).string(), cv::IMREAD_COLOR);
    ASSERT_EQ(bgr.size(), frames[i].bgr.size());
    EXPECT_EQ(cv::norm(bgr, frames[i].bgr, cv::NORM_INF), 0.0) << "colour of frame " << i;
    const cv::Mat depth = cv::imread((replay.out_dir / ("depth_" + seq + ".png")).string(), cv::IMREAD_ANYDEPTH);
    ExpectDepthMatches(depth, frames[i].depth_m, &worst_error_m, &worst_allowed_m);
  }
  std::printf("worst depth error %.2f mm (allowed there %.2f mm)\n", worst_error_m * 1e3, worst_allowed_m * 1e3);
}

std::vector<int64_t> Column(const Replay& replay, const char* key) {
  std::vector<int64_t> values;
  for (const auto& f : replay.summary.at("frames")) values.push_back(f.at(key).get<int64_t>());
  return values;
}

// fakenect sleeps so that each line is replayed no earlier than the recorded spacing after the previous
// one (it does not make up for time spent reading files or in callbacks, nor for a late wake-up on a
// loaded machine). So host receive gaps are at least the recorded gaps, never less.
void ExpectHostPacing(const Replay& replay, const std::vector<testing::RecordedFrame>& recorded) {
  const auto host_ns = Column(replay, "depth_host_ns");
  ASSERT_EQ(host_ns.size(), recorded.size());
  for (size_t i = 1; i < host_ns.size(); ++i) {
    const double recorded_gap_ns = (recorded[i].host_time_s - recorded[i - 1].host_time_s) * 1e9;
    EXPECT_GE(static_cast<double>(host_ns[i] - host_ns[i - 1]), recorded_gap_ns - 0.1e6) << "frame " << i;
  }
}

// Device time onto host time with core FitClock: slope of host ns per 60 MHz tick and residuals.
ClockFit FitReplayClock(const Replay& replay) {
  const ClockFit fit = FitClock(Column(replay, "depth_ticks"), Column(replay, "depth_host_ns"));
  std::printf("clock fit: %.4f ns/tick (nominal %.4f), residual rms %.3f ms, max %.3f ms\n", fit.ns_per_tick,
              1e9 / 60e6, fit.residual_rms_ns * 1e-6, fit.residual_max_ns * 1e-6);
  return fit;
}

TEST(Kinect1Replay, TumFramesComeBackThroughFakenect) {
  const auto frames = testing::LoadTumDesk();
  const fs::path recording = testing::FreshDir("tum_replay");
  const auto recorded = testing::WriteTumRecording(recording / "rec", frames, 2516594411u);
  const Replay replay = RunReplay(recording / "rec", recording / "out");
  ExpectReplayMatches(replay, frames, recorded);
  EXPECT_EQ(replay.summary.at("counter_wraps"), 0);
  ExpectHostPacing(replay, recorded);
}

TEST(Kinect1Replay, CounterWrapIsUnwrapped) {
  const auto frames = testing::LoadTumDesk();
  const fs::path recording = testing::FreshDir("tum_wrap");
  // Three frames (about 6e6 ticks at 30 Hz) before the 32-bit counter wraps.
  const uint64_t first_ticks = (uint64_t{1} << 32) - 6'000'000;
  const auto recorded = testing::WriteTumRecording(recording / "rec", frames, first_ticks);
  ASSERT_GT(recorded.back().ticks, uint64_t{1} << 32);
  const Replay replay = RunReplay(recording / "rec", recording / "out");
  ExpectReplayMatches(replay, frames, recorded);
  EXPECT_EQ(replay.summary.at("counter_wraps"), 1);
  ExpectHostPacing(replay, recorded);
  // The fit runs on unwrapped ticks; across the wrap raw ticks would put the last frames 71.6 s early.
  EXPECT_GE(FitReplayClock(replay).ns_per_tick, 0.99 * 1e9 / 60e6);
}

// fakenect's replay runs late by the time spent reading files, in callbacks and in late wake-ups (tens of ms
// per frame on a loaded machine), and that lateness accumulates. Two bursts of three 30 Hz frames, 3 s
// apart, keep it small against the span the fit rests on; the fit must then find the 60 MHz rate, and
// map ticks onto receive times (core FitClock on unwrapped ticks, across a counter wrap).
TEST(Kinect1Replay, ClockFitRecoversTheDeviceRate) {
  auto frames = testing::LoadTumDesk();
  frames.resize(6);
  for (size_t i = 0; i < frames.size(); ++i)
    frames[i].depth_stamp_s = 1000.0 + (i < 3 ? 0.0 : 3.0) + static_cast<double>(i % 3) / 30.0;
  const fs::path recording = testing::FreshDir("tum_clock");
  const auto recorded = testing::WriteTumRecording(recording / "rec", frames, (uint64_t{1} << 32) - 90'000'000);
  const Replay replay = RunReplay(recording / "rec", recording / "out");
  ASSERT_EQ(replay.summary.at("frames").size(), frames.size());
  EXPECT_EQ(replay.summary.at("counter_wraps"), 1);
  ExpectHostPacing(replay, recorded);
  const ClockFit fit = FitReplayClock(replay);
  EXPECT_NEAR(fit.ns_per_tick, 1e9 / 60e6, 0.10 * 1e9 / 60e6);
  const auto ticks = Column(replay, "depth_ticks");
  const auto host_ns = Column(replay, "depth_host_ns");
  for (size_t i = 0; i < ticks.size(); ++i) EXPECT_NEAR(fit.HostNs(ticks[i]), host_ns[i], 150e6) << "frame " << i;
}

TEST(Kinect1Replay, AccelerometerSamplesReachTheirFrames) {
  auto frames = testing::LoadTumDesk();
  frames.resize(4);
  std::vector<TiltSample> tilts(frames.size());
  for (size_t i = 0; i < tilts.size(); ++i) {
    tilts[i].accel_raw[0] = static_cast<int16_t>(10 * i);
    tilts[i].accel_raw[1] = static_cast<int16_t>(-819 + static_cast<int>(i));
    tilts[i].accel_raw[2] = 40;
    tilts[i].tilt_deg = -3.5 + static_cast<double>(i);
    tilts[i].tilt_status = 0;
  }
  const fs::path recording = testing::FreshDir("tum_tilt");
  testing::WriteTumRecording(recording / "rec", frames, 1000, tilts);
  const Replay replay = RunReplay(recording / "rec", recording / "out", {"--tilt-interval-ms", "0"});
  const auto& got = replay.summary.at("frames");
  ASSERT_EQ(got.size(), frames.size());
  for (size_t i = 0; i < got.size(); ++i) {
    ASSERT_TRUE(got[i].contains("tilt")) << "frame " << i;
    const auto& tilt = got[i].at("tilt");
    EXPECT_EQ(tilt.at("accel_raw")[0], tilts[i].accel_raw[0]);
    EXPECT_EQ(tilt.at("accel_raw")[1], tilts[i].accel_raw[1]);
    EXPECT_DOUBLE_EQ(tilt.at("tilt_deg").get<double>(), tilts[i].tilt_deg);
    // libfreenect: counts / 819 * 9.80665 m/s^2.
    EXPECT_NEAR(tilt.at("accel_mps2")[1].get<double>(), tilts[i].accel_raw[1] / 819.0 * 9.80665, 1e-9);
  }
}

TEST(Kinect1Replay, ThrowingCallbackEndsTheStreamWithItsReason) {
  auto frames = testing::LoadTumDesk();
  frames.resize(4);
  const fs::path recording = testing::FreshDir("tum_throw");
  testing::WriteTumRecording(recording / "rec", frames, 5000);
  const Replay replay = RunReplay(recording / "rec", recording / "out", {"--throw-at-frame", "2"});
  EXPECT_EQ(replay.summary.at("frames").size(), 2u);
  EXPECT_TRUE(replay.summary.at("stream_ended").get<bool>());
  EXPECT_EQ(replay.summary.at("stream_end_reason"), "kinect1: the frame callback failed: stop requested by the test");
}

TEST(Kinect1Replay, MissingRecordingIsAClearDeviceError) {
  const fs::path dir = testing::FreshDir("no_recording");
  const auto result = RunProcess({KINECT_REPLAY_DUMP, (dir / "out").string()}, FakenectEnv(dir / "absent"),
                                 dir / "log.txt");
  EXPECT_EQ(result.exit_code, 3) << result.output;
  EXPECT_NE(result.output.find("holds no INDEX.txt"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace mocap::capture
