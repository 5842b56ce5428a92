// Replays in the daemon, in process: a source that replays a recording starts with the first session
// (not when the daemon opens it), the NDI emulator's replay plays from that TSTART, and a tracker whose
// bodies all lose their poses (a replay past its end) says so in the session.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <thread>

#include "capture/daemon/daemon.h"
#include "capture/daemon/daemon_address.h"
#include "capture/daemon/sources.h"
#include "capture/ndi/emulator.h"
#include "capture/ndi/recorded_trajectory.h"
#include "core/check.h"
#include "session/reader.h"
#include "test_dirs.h"

namespace mocap::capture {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
constexpr int kBurstFrames = 5;

// A replay that hands over its whole (tiny) recording the moment it starts, as fakenect does its first
// frames: whatever is not recording then is lost.
class BurstReplay final : public CaptureSource {
 public:
  BurstReplay() : CaptureSource("burst") {}
  ~BurstReplay() override { Close(); }
  StreamInfo stream_info() const override {
    CameraStreamInfo info;
    info.name = name();
    info.model = "test";
    info.color_camera = {32, 24, 30, 30, 15.5, 11.5, {}};
    info.depth_camera = info.color_camera;
    info.depth_unit_m = 0.001;
    return info;
  }
  nlohmann::json device_status() const override { return {{"kind", "burst"}}; }
  bool starts_with_session() const override { return true; }

 private:
  void DoOpen() override {}
  void DoStart(CaptureSink* sink) override {
    for (int k = 0; k < kBurstFrames; ++k) {
      CapturedFrame frame{name(), {}, cv::Mat(24, 32, CV_8UC3, cv::Scalar(k, 0, 0)), cv::Mat(24, 32, CV_16UC1, cv::Scalar(500))};
      frame.record.frame = frame.record.device_ticks = k;
      frame.record.stamp_ns = MonotonicNowNs();
      sink->PushFrame(std::move(frame));
    }
  }
  void DoStop() override {}
  void DoClose() override {}
};

// Before: the daemon started every source when it opened it, so the burst went nowhere.
TEST(CaptureReplay, DaemonStartsAReplayWithTheFirstSessionAndLetsItPlayOn) {
  const fs::path dir = testing::FreshCaptureDir("replay_burst");
  std::vector<std::unique_ptr<CaptureSource>> sources;
  sources.push_back(std::make_unique<BurstReplay>());
  sources.push_back(CreateSimulatedTracker({.stream = "trk", .bodies = 1, .rate_hz = 100}));
  const CaptureSource* burst = sources[0].get();
  const CaptureSource* live = sources[1].get();
  CaptureDaemon daemon({.sessions_dir = dir}, std::move(sources));
  EXPECT_EQ(burst->state(), DeviceState::kOpen) << "a replay waits for the session";
  EXPECT_EQ(live->state(), DeviceState::kStreaming) << "live devices stream at once";
  std::this_thread::sleep_for(100ms);
  daemon.StartSession("S");
  EXPECT_EQ(burst->state(), DeviceState::kStreaming);
  daemon.StopSession();
  daemon.StartSession("T");  // plays on: not started again
  daemon.StopSession();
  EXPECT_EQ(SessionReader::Open(dir / "S").frame_count("burst"), kBurstFrames);
  EXPECT_EQ(SessionReader::Open(dir / "T").frame_count("burst"), 0);
}

// One body at rest for 0.3 s (recording clock from 0), every 10 ms.
std::shared_ptr<ndi::RecordedTrajectory> ShortRecording() {
  ndi::RecordedBody body{"tool", {}};
  for (int k = 0; k <= 30; ++k)
    body.samples.push_back({k * 10'000'000LL, PoseStatus::kValid, Rigid3d(Eigen::Quaterniond::Identity(), {0, 0, -1.5})});
  return std::make_shared<ndi::RecordedTrajectory>(std::vector<ndi::RecordedBody>{body}, ndi::RecordedTrajectoryOptions{});
}

// Before: the NDI source tracked from the daemon's start, so a replay shorter than the wait for the
// session was over (every body MISSING) and the session said nothing about it.
TEST(CaptureReplay, NdiReplayStartsWithTheSessionAndItsEndIsAWarning) {
  const fs::path dir = testing::FreshCaptureDir("replay_ndi");
  ndi::Emulator emulator({.port = 0, .tracker = {.rate_hz = 100, .clock_from_tstart = true}}, ShortRecording());
  emulator.Start();
  NdiSourceOptions ndi;
  ndi.client.port = emulator.port();
  ndi.client.poll_rate_hz = 400;
  ndi.replay = true;
  ndi.no_pose_warning_s = 0.4;
  std::vector<std::unique_ptr<CaptureSource>> sources;
  sources.push_back(CreateNdiSource(ndi));
  CaptureDaemon daemon({.sessions_dir = dir}, std::move(sources));
  std::this_thread::sleep_for(500ms);  // longer than the recording
  daemon.StartSession("S");
  // The status shows how many markers the tracker measured on the tool (BX 0x0008): the emulated tool's
  // 4 while the replay plays, 0 once it has ended (MISSING).
  // The one tool is the emulator's first handle (no tool names in the options).
  const auto markers = nlohmann::json::json_pointer("/streams/ndi/bodies/handle-01/markers");
  int most_markers = -1;
  for (const auto until = std::chrono::steady_clock::now() + 1200ms; std::chrono::steady_clock::now() < until;) {
    const nlohmann::json status = daemon.Status();
    if (status.contains(markers)) most_markers = std::max(most_markers, status[markers].get<int>());
    std::this_thread::sleep_for(5ms);
  }
  EXPECT_EQ(most_markers, 4);
  const nlohmann::json status = daemon.Status();
  ASSERT_TRUE(status.contains(markers)) << status.dump();
  EXPECT_EQ(status[markers], 0) << "past the replay's end";
  daemon.StopSession();

  const SessionReader reader = SessionReader::Open(dir / "S");
  const auto records = reader.tracker_records("ndi");
  ASSERT_FALSE(records.empty());
  EXPECT_LE(records.front().device_frame, 1002) << "the replay did not start with the session";
  int64_t with_pose = 0;
  for (const TrackerRecord& r : records) with_pose += HasPose(r.status);
  EXPECT_GE(with_pose, 20);
  bool warned = false;
  for (const EventRecord& e : reader.events())
    warned |= e.stream == "ndi" && e.kind == "warning" && e.detail.find("no body has had a pose") != std::string::npos;
  EXPECT_TRUE(warned) << "MISSING bodies after the replay's end must not be silent";
  EXPECT_GT(emulator.stats().past_end_replies, 0u);
}

TEST(DaemonAddress, WrittenReadAndIgnoredOnceItsProcessIsGone) {
  const fs::path dir = testing::FreshCaptureDir("daemon_address");
  EXPECT_FALSE(ReadDaemonAddress(dir)) << "no file: no daemon";
  WriteDaemonAddress(dir, {"127.0.0.1", 45678, ::getpid()});
  const std::optional<DaemonAddress> read = ReadDaemonAddress(dir);
  ASSERT_TRUE(read);
  EXPECT_EQ(read->port, 45678);
  EXPECT_EQ(read->bind, "127.0.0.1");
  RemoveDaemonAddress(dir, ::getpid() + 1);
  EXPECT_TRUE(fs::exists(DaemonAddressFile(dir))) << "another daemon's file is left alone";
  RemoveDaemonAddress(dir, ::getpid());
  EXPECT_FALSE(fs::exists(DaemonAddressFile(dir)));

  const pid_t child = ::fork();  // a process that is gone: a daemon killed with SIGKILL
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);
  WriteDaemonAddress(dir, {"127.0.0.1", 45678, child});
  EXPECT_FALSE(ReadDaemonAddress(dir)) << "a stale file is ignored";
  std::ofstream(DaemonAddressFile(dir)) << "{\"port\": \"x\"}";
  EXPECT_THROW(ReadDaemonAddress(dir), InputError);
}

}  // namespace
}  // namespace mocap::capture
