// End to end, the daemon as a user starts it: a fakenect replay waits for `capture start` (it plays its
// recording once), and a rig whose control port is 0 is found by the client commands given only --rig.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "../kinect/subprocess.h"
#include "../kinect/tum_recording.h"
#include "capture/daemon/daemon_address.h"
#include "e2e_cli.h"
#include "session/reader.h"
#include "test_dirs.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using testing::Cli;
using testing::Endpoint;
using testing::Source;

constexpr double kReplayTrackerRateHz = 30;
constexpr int kReplayedFrames = 30;  // 1 s at 30 Hz

fs::path WriteRig(const fs::path& dir, int tracker_port, bool camera, const std::string& control) {
  const fs::path rig = dir / "rig.yaml";
  std::ofstream out(rig);
  out << "name: replay-e2e\ncapture:\n  sessions_dir: sessions\n" << control
      << "  tracker: {name: ndi, tcp: \"127.0.0.1:" << tracker_port << "\", rate_hz: " << 4 * kReplayTrackerRateHz << "}\n";
  if (camera) out << "  camera: {name: kinect1, index: 0}\n";
  return rig;
}

std::vector<testing::RecordedFrame> WriteReplay(const fs::path& dir) {
  const std::vector<testing::TumFrame> tum = testing::LoadTumDesk();
  std::vector<testing::TumFrame> frames;
  for (int i = 0; i < kReplayedFrames; ++i) {
    frames.push_back(tum[static_cast<size_t>(i) % tum.size()]);
    frames.back().depth_stamp_s = 2000.0 + i / 30.0;
  }
  return testing::WriteTumRecording(dir, frames, 777'000);
}

// Status polls until the camera replay has ended (a deadline, not a number of polls: a loaded host).
nlohmann::json WaitForReplayEnd(const fs::path& dir, int port) {
  nlohmann::json status;
  for (const auto deadline = std::chrono::steady_clock::now() + 60s; std::chrono::steady_clock::now() < deadline;) {
    status = testing::Status(dir, port);
    if (!Source(status, "kinect1").value("stream_ended", std::string()).empty()) break;
    std::this_thread::sleep_for(100ms);
  }
  return status;
}

// Before: the daemon started fakenect when it opened the device, so a recording shorter than the wait
// for `capture start` had played out and the session got no frame.
TEST(CaptureReplayE2E, FakenectReplayPlaysIntoTheFirstSessionFromItsStart) {
  const fs::path dir = testing::FreshCaptureDir("replay_waits");
  const auto recorded = WriteReplay(dir / "replay");
  Endpoint emulator = testing::StartEmulator(dir, 0, kReplayTrackerRateHz);
  Endpoint daemon = testing::StartDaemon(WriteRig(dir, emulator.port, true, ""), testing::FakenectEnv(dir / "replay"));
  std::this_thread::sleep_for(1500ms);  // longer than the whole recording
  const nlohmann::json idle = testing::Status(dir, daemon.port);
  for (const auto& source : idle["sources"]) {
    if (source["name"] == "kinect1") {
      EXPECT_EQ(source["state"], "open") << "a replay waits for the session";
    }
  }
  const std::string port = std::to_string(daemon.port);
  ASSERT_EQ(Cli(dir, {"capture", "start", "--name", "S", "--port", port}).first, 0) << daemon.process->Log();
  const nlohmann::json status = WaitForReplayEnd(dir, daemon.port);
  ASSERT_FALSE(Source(status, "kinect1").value("stream_ended", std::string()).empty()) << status.dump();
  ASSERT_EQ(Cli(dir, {"capture", "stop", "--port", port}).first, 0);

  const SessionReader reader = SessionReader::Open(dir / "sessions" / "S");
  ASSERT_EQ(reader.frame_count("kinect1"), kReplayedFrames) << daemon.process->Log();
  EXPECT_EQ(reader.frame("kinect1", 0).record.device_ticks, static_cast<int64_t>(recorded.front().ticks));
  // The manifest is written before the replay's first frame: the recording's camera all the same.
  const CameraStreamInfo* camera = reader.manifest().FindCamera("kinect1");
  ASSERT_NE(camera, nullptr);
  EXPECT_TRUE(camera->depth_registered_to_color);
  EXPECT_EQ(camera->depth_camera.fx, 525.0);
  bool end_said = false;
  for (const EventRecord& e : reader.events())
    end_said |= e.stream == "kinect1" && e.kind == "warning" && e.detail.find("camera replay ended") != std::string::npos;
  EXPECT_TRUE(end_said) << "the replay's end is a warning event of the session";
}

// Before: `capture status --rig R` with `control.port: 0` in R connected to port 0 and failed.
TEST(CaptureReplayE2E, RigWithControlPortZeroIsFoundByItsClients) {
  const fs::path dir = testing::FreshCaptureDir("port_zero");
  Endpoint emulator = testing::StartEmulator(dir, 0, kReplayTrackerRateHz);
  const fs::path rig = WriteRig(dir, emulator.port, false, "  control: {bind: 127.0.0.1, port: 0}\n");
  Endpoint daemon = testing::StartDaemon(rig, {}, {});
  EXPECT_GT(daemon.port, 0);
  const auto [status_rc, status] = Cli(dir, {"capture", "status", "--rig", rig.string()});
  ASSERT_EQ(status_rc, 0) << status.dump() << daemon.process->Log();
  EXPECT_EQ(status["state"], "idle");
  ASSERT_EQ(Cli(dir, {"capture", "start", "--name", "S", "--rig", rig.string()}).first, 0);
  std::this_thread::sleep_for(300ms);
  const auto [stop_rc, summary] = Cli(dir, {"capture", "stop", "--rig", rig.string()});
  ASSERT_EQ(stop_rc, 0) << summary.dump();
  EXPECT_EQ(summary["complete"], true);

  daemon.process->Signal(SIGTERM);
  ASSERT_EQ(daemon.process->Wait(10000), 0) << daemon.process->Log();
  EXPECT_FALSE(fs::exists(capture::DaemonAddressFile(dir / "sessions"))) << "removed when the daemon exits";
  EXPECT_NE(Cli(dir, {"capture", "status", "--rig", rig.string()}).first, 0);
  std::ifstream log(dir / "cli.log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("control.port is 0 and no running daemon wrote its port"), std::string::npos) << text;
}

}  // namespace
}  // namespace mocap
