// End to end: `mocaplabel capture daemon` with `mocaplabel ndi-emulator` on loopback and a Kinect1
// replayed by libfreenect's fakenect from real TUM frames, controlled with `capture start/stop`; and
// the faults: the tracker killed and restarted, corrupted bytes, the daemon killed or terminated.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "../kinect/subprocess.h"
#include "../kinect/tum_recording.h"
#include "capture/kinect/kinect1_depth.h"
#include "e2e_cli.h"
#include "process.h"
#include "session/reader.h"
#include "test_dirs.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using testing::ChildProcess;
using testing::Cli;
using testing::Endpoint;
using testing::Source;
using testing::StartDaemon;
using testing::Status;

constexpr double kTrackerRateHz = 30;
// 2 s at 30 Hz: the 9 TUM frames over and over. The replay starts with `capture start` (the daemon
// starts replays with the first session). Longer would risk the writer falling 32 frames behind on a
// loaded host, which the test rightly counts as a failure.
constexpr int kReplayFrames = 60;

Endpoint StartEmulator(const fs::path& dir, int port, const std::vector<std::string>& extra = {}) {
  return testing::StartEmulator(dir, port, kTrackerRateHz, extra);
}

fs::path WriteRig(const fs::path& dir, int tracker_port, bool camera) {
  const fs::path rig = dir / "rig.yaml";
  std::ofstream out(rig);
  out << "name: e2e\ncapture:\n  sessions_dir: sessions\n"
      << "  tracker: {name: ndi, tcp: \"127.0.0.1:" << tracker_port << "\", rate_hz: " << 8 * kTrackerRateHz << "}\n";
  if (camera) out << "  camera: {name: kinect1, index: 0}\n";
  return rig;
}

struct TruthRow {
  Rigid3d pose;
  std::string status;
};
// The emulator's --truth CSV: (frame, handle) -> what it served.
std::map<std::pair<int64_t, int>, TruthRow> ReadTruth(const fs::path& csv) {
  std::map<std::pair<int64_t, int>, TruthRow> truth;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::vector<std::string> f;
    for (std::string cell; std::getline(row, cell, ',');) f.push_back(cell);
    if (f.size() != 12 || f[11] == "1") continue;  // a corrupted reply was never delivered
    const Rigid3d pose = f[2] != "valid" ? Rigid3d()
                         : Rigid3d::FromQuatWxyz(std::stod(f[6]), std::stod(f[7]), std::stod(f[8]), std::stod(f[9]),
                                                 {std::stod(f[3]), std::stod(f[4]), std::stod(f[5])});
    truth[{std::stoll(f[0]), std::stoi(f[1])}] = {pose, f[2]};
  }
  return truth;
}

int HandleOf(const std::string& body) { return std::stoi(body.substr(body.find('-') + 1), nullptr, 16); }

std::vector<testing::TumFrame> ReplayFrames() {
  const std::vector<testing::TumFrame> tum = testing::LoadTumDesk();
  std::vector<testing::TumFrame> frames;
  for (int i = 0; i < kReplayFrames; ++i) {
    testing::TumFrame f = tum[static_cast<size_t>(i) % tum.size()];
    f.depth_stamp_s = 1000.0 + i / 30.0;
    frames.push_back(f);
  }
  return frames;
}

// The depth in mm the Kinect1 device delivers for a recorded depth (the fit of the raw code written).
cv::Mat ExpectedDepthMm(const cv::Mat& depth_m) {
  const capture::Raw11ToMmTable table = capture::Raw11ToMmTable::FromFit();
  cv::Mat mm(depth_m.size(), CV_16UC1);
  for (int v = 0; v < depth_m.rows; ++v)
    for (int u = 0; u < depth_m.cols; ++u) {
      const float z = depth_m.at<float>(v, u);
      mm.at<uint16_t>(v, u) = z == 0 ? 0 : table[capture::DepthMToRaw11(z)];
    }
  return mm;
}

void ExpectCameraMatchesReplay(const SessionReader& reader, const std::vector<testing::TumFrame>& frames,
                               const std::vector<testing::RecordedFrame>& recorded) {
  const int64_t n = reader.frame_count("kinect1");
  ASSERT_GT(n, 5);
  int64_t first = -1;
  for (size_t k = 0; k < recorded.size(); ++k)
    if (static_cast<int64_t>(recorded[k].ticks) == reader.frame("kinect1", 0).record.device_ticks) first = static_cast<int64_t>(k);
  ASSERT_GE(first, 0) << "the first frame's device ticks are not in the recording";
  EXPECT_EQ(first, 0) << "the replay did not start with the session";
  // Every frame the replay served after `start` is in the session, in order, once.
  ASSERT_EQ(n, kReplayFrames - first);
  for (int64_t i = 0; i < n; ++i) {
    const CameraFrameRecord& r = reader.frame("kinect1", i).record;
    EXPECT_EQ(r.device_ticks, static_cast<int64_t>(recorded[static_cast<size_t>(first + i)].ticks)) << i;
    EXPECT_EQ(r.frame, reader.frame("kinect1", 0).record.frame + i);
    if (i > 0) {
      EXPECT_GT(r.stamp_ns, reader.frame("kinect1", i - 1).record.stamp_ns);
    }
  }
  // Host stamps follow the recording's clock: the replay sleeps its spacing, so a frame is never
  // received earlier (after the first) than the recording says, less the first frame's receive delay
  // (100 ms on a loaded host, as for the tracker); a busy host only delays frames, at most doubling the
  // span. Compared per frame with what was served, not as a ratio of a few frames' span, which one
  // late first frame distorts when `start` came late and few frames were recorded.
  const double served_first_s = frames[static_cast<size_t>(first)].depth_stamp_s;
  const int64_t stamp_first_ns = reader.frame("kinect1", 0).record.stamp_ns;
  for (int64_t i = 0; i < n; ++i) {
    const double served_s = frames[static_cast<size_t>(first + i)].depth_stamp_s - served_first_s;
    const double received_s = (reader.frame("kinect1", i).record.stamp_ns - stamp_first_ns) * 1e-9;
    EXPECT_GT(received_s, served_s - 0.1) << "frame " << i << " received before the replay served it";
  }
  const double served_span_s = frames[static_cast<size_t>(first + n - 1)].depth_stamp_s - served_first_s;
  const double span_s = (reader.frame("kinect1", n - 1).record.stamp_ns - stamp_first_ns) * 1e-9;
  EXPECT_LT(span_s, served_span_s * 2.0 + 0.1);
  for (const int64_t i : {int64_t{0}, n - 1}) {
    const testing::TumFrame& f = frames[static_cast<size_t>(first + i)];
    EXPECT_EQ(cv::norm(reader.LoadColor("kinect1", i), f.bgr, cv::NORM_INF), 0.0) << "colour of frame " << i;
    const cv::Mat depth_mm = cv::imread(reader.DepthPath("kinect1", i).string(), cv::IMREAD_ANYDEPTH);  // mm
    EXPECT_EQ(cv::norm(depth_mm, ExpectedDepthMm(f.depth_m), cv::NORM_INF), 0.0) << "depth of frame " << i;
  }
}

// Least-squares line stamp_ns = intercept + slope * (device_frame - the first's): {intercept, slope}.
std::pair<double, double> FitLine(const std::vector<TrackerRecord>& body) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const TrackerRecord& r : body) {
    const double x = static_cast<double>(r.device_frame - body.front().device_frame);
    const double y = static_cast<double>(r.stamp_ns - body.front().stamp_ns);  // small numbers: no cancellation
    n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  return {static_cast<double>(body.front().stamp_ns) + (sy - slope * sx) / n, slope};
}

void ExpectTrackerMatchesEmulator(const SessionReader& reader, const fs::path& truth_csv, const nlohmann::json& info) {
  const auto truth = ReadTruth(truth_csv);
  const auto records = reader.tracker_records("ndi");
  ASSERT_GT(records.size(), 20u);
  std::set<std::pair<int64_t, int>> seen;
  int64_t first = INT64_MAX, last = 0;
  for (const TrackerRecord& r : records) {
    const auto key = std::make_pair(r.device_frame, HandleOf(r.body));
    const auto it = truth.find(key);
    ASSERT_NE(it, truth.end()) << "frame " << r.device_frame << " " << r.body << " was never served";
    EXPECT_TRUE(seen.insert(key).second) << "recorded twice";
    first = std::min(first, r.device_frame);
    last = std::max(last, r.device_frame);
    if (it->second.status != "valid") continue;
    EXPECT_LT((r.T_frame_body.translation() - it->second.pose.translation()).norm(), 2e-6);
    EXPECT_LT(r.T_frame_body.rotation().angularDistance(it->second.pose.rotation()), 2e-5);
  }
  int64_t served_in_range = 0, unserved_frames = 0;
  std::set<int64_t> frames_served;
  for (const auto& [key, row] : truth)
    if (key.first >= first && key.first <= last) {
      ++served_in_range;
      frames_served.insert(key.first);
    }
  EXPECT_EQ(static_cast<int64_t>(seen.size()), served_in_range) << "samples served during the session are missing";
  unserved_frames = (last - first + 1) - static_cast<int64_t>(frames_served.size());
  // Stamps against frame numbers: the emulator's rate (its frame numbers come from its clock), receive
  // jitter well under a frame or two. The line is fitted through every sample: a line through the first
  // and last alone tilts by their receive delays (100 ms over a 2 s session is 5 %).
  const auto body = reader.BodyRecords("ndi", records.front().body);
  const auto [intercept_ns, slope_ns] = FitLine(body);
  EXPECT_NEAR(slope_ns, 1e9 / kTrackerRateHz, 0.05e9 / kTrackerRateHz);
  for (const TrackerRecord& r : body) {
    const double predicted = intercept_ns + (r.device_frame - body.front().device_frame) * slope_ns;
    EXPECT_LT(std::abs(r.stamp_ns - predicted), 100e6) << "frame " << r.device_frame;  // a loaded CI host
  }
  if (!info.contains("tracker_bodies")) return;  // no `info` document to compare with
  for (const auto& [name, b] : info["tracker_bodies"].items())
    EXPECT_EQ(b["dropped_frames"], unserved_frames) << name << ": skipped frame numbers the emulator did serve";
}

TEST(CaptureDaemonE2E, RecordsWhatTheEmulatorAndTheReplayServed) {
  const fs::path dir = testing::FreshCaptureDir("e2e_clean");
  const std::vector<testing::TumFrame> frames = ReplayFrames();
  const auto recorded = testing::WriteTumRecording(dir / "replay", frames, 123'456'789);
  Endpoint emulator = StartEmulator(dir, 0);
  Endpoint daemon = StartDaemon(WriteRig(dir, emulator.port, true), testing::FakenectEnv(dir / "replay"));
  const std::string port = std::to_string(daemon.port);
  const auto [start_rc, started] = Cli(dir, {"capture", "start", "--name", "S", "--port", port});
  ASSERT_EQ(start_rc, 0) << started.dump() << daemon.process->Log();
  // Until the replay has served its last frame, and `status` has shown the tracked body visible. A
  // deadline, not a number of polls: each poll is a `capture status` process, slow on a loaded host.
  nlohmann::json status;
  bool ended = false, visible = false;
  for (const auto deadline = std::chrono::steady_clock::now() + 60s; !(ended && visible) && std::chrono::steady_clock::now() < deadline;) {
    status = Status(dir, daemon.port);
    if (!status.is_object() || !status.contains("sources")) {  // a poll that timed out on a loaded host: retry
      std::this_thread::sleep_for(100ms);
      continue;
    }
    ended = !Source(status, "kinect1").value("stream_ended", std::string()).empty();
    // Visible: a pose within the last 0.5 s; one poll may fall into a stall of a loaded host.
    visible = visible || status["streams"]["ndi"]["bodies"]["handle-01"]["visible"] == true;
    if (!(ended && visible)) std::this_thread::sleep_for(100ms);
  }
  ASSERT_TRUE(ended) << status.dump();
  EXPECT_TRUE(visible) << status.dump();
  std::this_thread::sleep_for(300ms);
  const auto [stop_rc, summary] = Cli(dir, {"capture", "stop", "--port", port});
  ASSERT_EQ(stop_rc, 0) << summary.dump();
  EXPECT_EQ(summary["complete"], true);
  EXPECT_EQ(summary["streams"]["kinect1"]["dropped"], 0);
  EXPECT_EQ(summary["streams"]["ndi"]["dropped"], 0);
  emulator.process->Signal(SIGTERM);
  emulator.process->Wait(5000);

  const fs::path session = dir / "sessions" / "S";
  const auto [info_rc, info] = Cli(dir, {"info", session.string()});
  ASSERT_EQ(info_rc, 0) << info.dump();
  EXPECT_EQ(info["events"].value("drop", 0), 0) << info["events"].dump();
  EXPECT_EQ(info["cameras"]["kinect1"]["dropped_frames"], 0);
  const SessionReader reader = SessionReader::Open(session);
  EXPECT_TRUE(reader.complete());
  ExpectCameraMatchesReplay(reader, frames, recorded);
  ExpectTrackerMatchesEmulator(reader, dir / "truth.csv", info);
}

TEST(CaptureDaemonE2E, TrackerKilledAndRestartedLeavesAGapAndRecordingContinues) {
  const fs::path dir = testing::FreshCaptureDir("e2e_restart");
  Endpoint emulator = StartEmulator(dir, 0);
  const int tracker_port = emulator.port;
  Endpoint daemon = StartDaemon(WriteRig(dir, tracker_port, false), {});
  const std::string port = std::to_string(daemon.port);
  ASSERT_EQ(Cli(dir, {"capture", "start", "--name", "S", "--port", port}).first, 0);
  std::this_thread::sleep_for(800ms);
  emulator.process->Signal(SIGKILL);
  emulator.process->Wait(5000);
  std::this_thread::sleep_for(700ms);
  Endpoint restarted = StartEmulator(dir, tracker_port);
  for (int i = 0; i < 80 && Source(Status(dir, daemon.port), "ndi")["reconnects"] == 0; ++i) std::this_thread::sleep_for(100ms);
  std::this_thread::sleep_for(600ms);
  const auto [stop_rc, summary] = Cli(dir, {"capture", "stop", "--port", port});
  ASSERT_EQ(stop_rc, 0) << summary.dump() << daemon.process->Log();

  const SessionReader reader = SessionReader::Open(dir / "sessions" / "S");
  std::optional<int64_t> gap_ns;
  std::set<std::string> kinds;
  for (const EventRecord& e : reader.events()) {
    if (e.stream == "ndi") kinds.insert(e.kind);
    if (e.kind == "gap" && e.stream == "ndi") gap_ns = e.stamp_ns;
  }
  ASSERT_TRUE(gap_ns) << "no gap event; log:\n" << daemon.process->Log();
  EXPECT_TRUE(kinds.count("error") && kinds.count("reconnect"));
  int64_t before = 0, after = 0;
  for (const TrackerRecord& r : reader.tracker_records("ndi")) (r.stamp_ns < *gap_ns ? before : after)++;
  EXPECT_GT(before, 20);
  EXPECT_GT(after, 10) << "recording did not continue after the reconnect";
}

TEST(CaptureDaemonE2E, CorruptedBytesAreCountedAndRecordingContinues) {
  const fs::path dir = testing::FreshCaptureDir("e2e_corrupt");
  Endpoint emulator = StartEmulator(dir, 0, {"--corrupt", "0.3"});
  Endpoint daemon = StartDaemon(WriteRig(dir, emulator.port, false), {});
  const std::string port = std::to_string(daemon.port);
  ASSERT_EQ(Cli(dir, {"capture", "start", "--name", "S", "--port", port}).first, 0);
  std::this_thread::sleep_for(1500ms);
  const nlohmann::json device = Source(Status(dir, daemon.port), "ndi");
  EXPECT_GT(device["crc_errors"].get<int64_t>() + device["malformed_replies"].get<int64_t>(), 0) << device.dump();
  const auto [stop_rc, summary] = Cli(dir, {"capture", "stop", "--port", port});
  ASSERT_EQ(stop_rc, 0) << summary.dump();
  EXPECT_FALSE(daemon.process->Wait(0)) << "the daemon exited";
  const SessionReader reader = SessionReader::Open(dir / "sessions" / "S");
  EXPECT_GT(reader.tracker_records("ndi").size(), 20u);
  int64_t errors = 0;
  for (const EventRecord& e : reader.events()) errors += e.kind == "error";
  EXPECT_GT(errors, 0);
  ExpectTrackerMatchesEmulator(reader, dir / "truth.csv", nlohmann::json::object());  // never a damaged pose
}

TEST(CaptureDaemonE2E, SigkillLeavesAReadableSessionAndSigtermFinishesIt) {
  const fs::path dir = testing::FreshCaptureDir("e2e_signals");
  testing::WriteTumRecording(dir / "replay", ReplayFrames(), 1000);
  Endpoint emulator = StartEmulator(dir, 0);
  const fs::path rig = WriteRig(dir, emulator.port, true);
  {
    Endpoint daemon = StartDaemon(rig, testing::FakenectEnv(dir / "replay"));
    ASSERT_EQ(Cli(dir, {"capture", "start", "--name", "killed", "--port", std::to_string(daemon.port)}).first, 0);
    std::this_thread::sleep_for(1500ms);
    daemon.process->Signal(SIGKILL);
    EXPECT_EQ(daemon.process->Wait(5000), 128 + SIGKILL);
  }
  const SessionReader killed = SessionReader::Open(dir / "sessions" / "killed");
  EXPECT_FALSE(killed.complete());
  EXPECT_GT(killed.tracker_records("ndi").size(), 10u);
  EXPECT_GT(killed.frame_count("kinect1"), 5);
  for (int64_t i = 0; i < killed.frame_count("kinect1"); ++i) killed.LoadDepth("kinect1", i);

  Endpoint daemon = StartDaemon(rig, testing::FakenectEnv(dir / "replay"));
  ASSERT_EQ(Cli(dir, {"capture", "start", "--name", "terminated", "--port", std::to_string(daemon.port)}).first, 0);
  std::this_thread::sleep_for(800ms);
  daemon.process->Signal(SIGTERM);
  EXPECT_EQ(daemon.process->Wait(10000), 0) << daemon.process->Log();
  const SessionReader terminated = SessionReader::Open(dir / "sessions" / "terminated");
  EXPECT_TRUE(terminated.complete());
  EXPECT_GT(terminated.tracker_records("ndi").size(), 10u);
}

}  // namespace
}  // namespace mocap
