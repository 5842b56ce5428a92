// `mocaplabel ndi-emulator --replay S` as a user runs it: the replay starts when the client starts
// tracking (TSTART), however late it connects, and running past the recording's end is said on stderr.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "capture/ndi/client.h"
#include "session/writer.h"

namespace mocap::ndi {
namespace {

namespace fs = std::filesystem;
constexpr double kRecordingS = 1.0;
constexpr double kRateHz = 60;

// A session with one tracker body at rest for kRecordingS, sampled at kRateHz.
fs::path WriteTrackerSession(const fs::path& dir) {
  SessionManifest manifest;
  manifest.source = "test";
  manifest.trackers.push_back({"ndi", "polaris", "", "tracker", {"tool"}});
  auto writer = SessionWriter::Create(dir, manifest);
  for (int k = 0; k <= static_cast<int>(kRecordingS * kRateHz); ++k) {
    TrackerRecord record;
    record.body = "tool";
    record.device_frame = k;
    record.stamp_ns = 5'000'000'000 + static_cast<int64_t>(k * 1e9 / kRateHz);
    record.status = PoseStatus::kValid;
    record.T_frame_body = Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.1, 0.2, -1.5));
    writer->WriteTrackerSample("ndi", record);
  }
  writer->Close();
  return dir;
}

std::string ReadAll(const fs::path& file) {
  std::stringstream text;
  text << std::ifstream(file).rdbuf();
  return text.str();
}

TEST(NdiEmulatorCli, ReplayStartsAtTheClientsTstartAndSaysWhenItEnded) {
  const fs::path dir = fs::temp_directory_path() / ("ndi_replay_cli_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path session = WriteTrackerSession(dir / "S");
  const std::string command = std::string(MOCAP_BINARY_DIR) + "/src/cli/mocaplabel ndi-emulator --port 0 --json --duration 5 " +
                              "--replay " + session.string() + " 2> " + (dir / "emulator.log").string();
  std::FILE* process = ::popen(command.c_str(), "r");
  ASSERT_NE(process, nullptr);
  char line[512] = {};
  ASSERT_NE(std::fgets(line, sizeof(line), process), nullptr);
  const nlohmann::json where = nlohmann::json::parse(line);
  // Longer than the whole recording: before the fix the emulator's clock had run past it, all MISSING.
  std::this_thread::sleep_for(std::chrono::duration<double>(kRecordingS + 0.5));

  std::mutex mutex;
  int with_pose = 0, without_pose = 0;
  NdiClient client({.port = where["port"].get<int>(), .poll_rate_hz = 120}, [&](const TrackerSample& s) {
    std::lock_guard lock(mutex);
    for (const BodySample& b : s.bodies) (b.has_pose ? with_pose : without_pose)++;
  }, nullptr);
  client.Open();
  client.StartStreaming();
  std::this_thread::sleep_for(std::chrono::duration<double>(kRecordingS + 0.8));  // the whole replay, then past it
  client.Close();
  EXPECT_EQ(::pclose(process), 0);

  std::lock_guard lock(mutex);
  EXPECT_GT(with_pose, 30) << "the recording was not played from the client's TSTART";
  EXPECT_GT(without_pose, 5) << "after the recording's end every body is MISSING";
  const std::string log = ReadAll(dir / "emulator.log");
  EXPECT_NE(log.find("replayed recording ended at tracking time 1.00 s"), std::string::npos) << log;
  EXPECT_NE(log.find("past the replay's end"), std::string::npos) << log;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mocap::ndi
