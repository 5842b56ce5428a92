// The pipeline in process: bounded queues, the Recorder with simulated sources, drops that are
// counted and logged, and a disk that fills.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <thread>

#include "capture/daemon/bounded_queue.h"
#include "capture/daemon/daemon.h"
#include "capture/daemon/recorder.h"
#include "capture/daemon/sources.h"
#include "session/reader.h"
#include "session/stats.h"
#include "../session/full_disk.h"
#include "test_dirs.h"

namespace mocap::capture {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

SessionManifest ManifestOf(const std::vector<const CaptureSource*>& sources) {
  SessionManifest manifest;
  manifest.source = "capture";
  for (const CaptureSource* source : sources) AddStream(manifest, source->stream_info());
  return manifest;
}

TEST(BoundedQueue, RefusesWhenFullAndDrainsAfterStop) {
  BoundedQueue<int> queue(2);
  EXPECT_TRUE(queue.TryPush(1));
  EXPECT_TRUE(queue.TryPush(2));
  EXPECT_FALSE(queue.TryPush(3));
  EXPECT_EQ(queue.high_water(), 2u);
  queue.Stop();
  EXPECT_FALSE(queue.TryPush(4));
  EXPECT_EQ(queue.Pop(), 1);
  EXPECT_EQ(queue.Pop(), 2);
  EXPECT_EQ(queue.Pop(), std::nullopt);
}

TEST(Recorder, RecordsSimulatedSourcesWithoutDrops) {
  const fs::path dir = testing::FreshCaptureDir("recorder_clean") / "S";
  auto camera = CreateSimulatedCamera({.stream = "cam", .width = 160, .height = 120, .rate_hz = 100, .max_frames = 20});
  auto tracker = CreateSimulatedTracker({.stream = "trk", .bodies = 3, .rate_hz = 1000, .max_frames = 200});
  auto recorder = Recorder::Start({.session_dir = dir}, ManifestOf({camera.get(), tracker.get()}));
  camera->Open();
  tracker->Open();
  camera->Start(recorder.get());
  tracker->Start(recorder.get());
  std::this_thread::sleep_for(1000ms);  // both stop by themselves after 0.2 s
  camera->Close();
  tracker->Close();
  const RecorderSummary summary = recorder->Stop();
  EXPECT_TRUE(summary.complete) << summary.error;
  EXPECT_EQ(summary.streams.at("cam").written, 20);
  EXPECT_EQ(summary.streams.at("cam").dropped, 0);
  EXPECT_EQ(summary.streams.at("trk").written, 600);
  const SessionReader reader = SessionReader::Open(dir);
  EXPECT_TRUE(reader.complete());
  ASSERT_EQ(reader.frame_count("cam"), 20);
  for (int64_t i = 0; i < 20; ++i) EXPECT_EQ(reader.frame("cam", i).record.frame, i);
  EXPECT_EQ(reader.LoadColor("cam", 19).cols, 160);
  EXPECT_EQ(reader.BodyRecords("trk", "body2").size(), 200u);
  // Each device clock fitted onto the host clock: a 60 MHz counter (a Kinect1's), one tracker frame per ms.
  const auto& fits = reader.manifest().clock_fits;
  ASSERT_TRUE(fits.count("cam") && fits.count("trk"));
  EXPECT_NEAR(fits.at("cam").ns_per_tick, 1e9 / 60e6, 0.1 * 1e9 / 60e6) << "paced at 100 Hz; late wake-ups are outliers";
  EXPECT_EQ(fits.at("cam").samples, 19) << "frame 0 has no device time";
  EXPECT_NEAR(fits.at("trk").ns_per_tick, 1e6, 0.1 * 1e6);
  EXPECT_EQ(fits.at("trk").samples, 199) << "one pair per tracker frame, not per body";
}

TEST(ClockSamples, KeepsOnePairPerDeviceValueAndThinsLongStreams) {
  ClockSamples clocks(/*max_pairs=*/100);
  for (int64_t f = 1; f <= 1000; ++f)
    for (int body = 0; body < 3; ++body) clocks.Add("trk", f, 7'000'000 + f * 1'000'000 + body * 1000);
  const std::map<std::string, ClockFit> fits = clocks.Fit();
  ASSERT_TRUE(fits.count("trk"));
  EXPECT_LE(fits.at("trk").samples, 100);
  EXPECT_GE(fits.at("trk").samples, 50);
  EXPECT_NEAR(fits.at("trk").ns_per_tick, 1e6, 1e-3);
  EXPECT_NEAR(static_cast<double>(fits.at("trk").HostNs(500)), 507'000'000.0, 1.0) << "the first receive of frame 500";
  ClockSamples constant;
  constant.Add("cam", 5, 1);
  constant.Add("cam", 5, 2);
  EXPECT_TRUE(constant.Fit().empty()) << "a clock that never changed is not fitted";
}

TEST(Recorder, DropsWhenTheWriterFallsBehindAreCountedAndLogged) {
  const fs::path dir = testing::FreshCaptureDir("recorder_drops") / "S";
  auto camera = CreateSimulatedCamera({.stream = "cam", .width = 640, .height = 480, .rate_hz = 0});
  RecorderOptions options{.session_dir = dir, .frame_queue = 1};
  options.writer.encoder_threads = 1;
  options.writer.max_pending_frames = 1;
  auto recorder = Recorder::Start(options, ManifestOf({camera.get()}));
  const cv::Mat color(480, 640, CV_8UC3, cv::Scalar(10, 20, 30)), depth(480, 640, CV_16UC1, cv::Scalar(1000));
  for (int64_t i = 0; i < 60; ++i)  // far faster than one encoder thread writes 640x480 PNGs
    recorder->PushFrame({"cam", {i, 0, MonotonicNowNs(), "", "", ""}, color.clone(), depth.clone()});
  const RecorderSummary summary = recorder->Stop();
  const StreamCounters& c = summary.streams.at("cam");
  EXPECT_TRUE(summary.complete);
  EXPECT_EQ(c.received, 60);
  EXPECT_GT(c.dropped, 0);
  EXPECT_EQ(c.written + c.dropped, 60);
  const SessionReader reader = SessionReader::Open(dir);
  EXPECT_EQ(reader.frame_count("cam"), c.written);
  int64_t logged = 0;
  for (const EventRecord& e : reader.events())
    if (e.kind == "drop") logged += std::stoll(e.detail.substr(0, e.detail.find(' ')));
  EXPECT_EQ(logged, c.dropped);  // every drop is in the event log
  // And visible as skipped frame numbers (those before the first and after the last written aside).
  const int64_t leading = reader.frame("cam", 0).record.frame;
  const int64_t trailing = 59 - reader.frame("cam", reader.frame_count("cam") - 1).record.frame;
  EXPECT_EQ(ComputeSessionStats(reader).cameras.at(0).dropped_frames + leading + trailing, c.dropped);
}

// In a child with its own mount namespace: the daemon records into a 1 MiB tmpfs until it is full.
std::string FillDiskThroughDaemon(const fs::path& mount_point) {
  return testing::RunOnFullDiskInChild(mount_point, [&](const testing::SayFn& say) {
    try {
      std::vector<std::unique_ptr<CaptureSource>> sources;
      sources.push_back(CreateSimulatedCamera({.stream = "cam", .width = 320, .height = 240, .rate_hz = 200}));
      sources.push_back(CreateSimulatedTracker({.stream = "trk", .rate_hz = 400}));
      CaptureDaemon daemon({.sessions_dir = mount_point}, std::move(sources));
      daemon.StartSession("S");
      for (int i = 0; i < 100 && daemon.Status()["state"] != "failed"; ++i) std::this_thread::sleep_for(50ms);
      const nlohmann::json status = daemon.Status();
      if (status["state"] != "failed") say("FAIL the session did not stop: " + status.dump());
      const nlohmann::json summary = daemon.StopSession();
      const std::string error = summary["error"];
      if (error.find("No space left on device") == std::string::npos) say("FAIL expected ENOSPC, got: " + error);
      if (summary["complete"] != false) say("FAIL a failed session is marked complete");
      const SessionReader reader = SessionReader::Open(mount_point / "S");
      if (reader.complete()) say("FAIL the manifest says complete");
      if (reader.frame_count("cam") == 0) say("FAIL not one frame was written before the disk was full");
      for (int64_t i = 0; i < reader.frame_count("cam"); ++i) reader.LoadColor("cam", i);
      say("OK " + std::to_string(reader.frame_count("cam")) + " whole frames; error: " + error);
    } catch (const std::exception& e) {
      say(std::string("FAIL ") + e.what());
    }
  });
}

TEST(CaptureDaemon, FullDiskStopsTheSessionWithAClearError) {
  const std::string result = FillDiskThroughDaemon(testing::FreshCaptureDir("disk_full"));
  if (result.rfind("SKIP", 0) == 0) GTEST_SKIP() << result;
  EXPECT_EQ(result.rfind("OK", 0), 0u) << result;
  std::printf("%s\n", result.c_str());
}

TEST(CaptureDaemon, SessionsStartStopAndRefuseBadRequests) {
  const fs::path root = testing::FreshCaptureDir("daemon_sessions");
  std::vector<std::unique_ptr<CaptureSource>> sources;
  sources.push_back(CreateSimulatedCamera({.stream = "cam", .width = 160, .height = 120, .rate_hz = 30}));
  sources.push_back(CreateSimulatedTracker({.stream = "trk", .bodies = 2, .rate_hz = 100}));
  CaptureDaemon daemon({.sessions_dir = root}, std::move(sources));
  EXPECT_THROW(daemon.StopSession(), StateError);
  EXPECT_THROW(daemon.StartSession("../escape"), InputError);
  EXPECT_THROW(daemon.StartSession(""), InputError);
  daemon.StartSession("one");
  EXPECT_THROW(daemon.StartSession("two"), StateError);
  std::this_thread::sleep_for(1200ms);
  const nlohmann::json status = daemon.Status();
  EXPECT_EQ(status["state"], "recording");
  EXPECT_NEAR(status["streams"]["trk"]["rate_hz"].get<double>(), 100, 25);
  EXPECT_NEAR(status["streams"]["cam"]["rate_hz"].get<double>(), 30, 10);
  EXPECT_EQ(status["streams"]["trk"]["bodies"]["body1"]["visible"], true);
  EXPECT_GT(status["disk"]["free_bytes"].get<uint64_t>(), 0u);
  EXPECT_TRUE(status["queues"].contains("frames"));
  const nlohmann::json summary = daemon.StopSession();
  EXPECT_EQ(summary["complete"], true);
  EXPECT_EQ(summary["streams"]["cam"]["dropped"], 0);
  EXPECT_THROW(daemon.StartSession("one"), InputError);  // exists already
  EXPECT_TRUE(SessionReader::Open(root / "one").complete());
}

}  // namespace
}  // namespace mocap::capture
