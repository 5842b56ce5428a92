// `mocaplabel ndi-emulator` as a user runs it: a separate process on loopback, a client connected to
// it, and the samples compared with the --truth file the command writes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "capture/ndi/client.h"

namespace mocap::ndi {
namespace {

struct TruthRow {
  std::string status;
  Eigen::Vector3d t_m;
};

std::map<std::pair<uint32_t, int>, TruthRow> ReadTruth(const std::filesystem::path& path) {
  std::map<std::pair<uint32_t, int>, TruthRow> rows;
  std::ifstream file(path);
  std::string line;
  std::getline(file, line);  // header
  while (std::getline(file, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream in(line);
    uint32_t frame;
    int handle;
    TruthRow row;
    in >> frame >> handle >> row.status >> row.t_m.x() >> row.t_m.y() >> row.t_m.z();
    rows[{frame, handle}] = row;
  }
  return rows;
}

TEST(NdiEmulatorCli, ServesWhatItsTruthFileRecords) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("ndi_cli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "script.txt") << "static ref 0 0 -1500\ncircle wand 0 0 -1500 120 3\n";
  const std::string command = std::string(MOCAP_BINARY_DIR) + "/src/cli/mocaplabel ndi-emulator --port 0 --json " +
                              "--rate 100 --noise-mm 0.3 --dropout 0.3 --duration 3 --script " + (dir / "script.txt").string() +
                              " --truth " + (dir / "truth.csv").string();
  std::FILE* process = ::popen(command.c_str(), "r");
  ASSERT_NE(process, nullptr);
  char line[512] = {};
  ASSERT_NE(std::fgets(line, sizeof(line), process), nullptr);
  const nlohmann::json where = nlohmann::json::parse(line);
  EXPECT_EQ(where["bodies"], (nlohmann::json{"ref", "wand"}));

  std::mutex mutex;
  std::vector<TrackerSample> samples;
  NdiClient client({.port = where["port"].get<int>(), .poll_rate_hz = 100}, [&](const TrackerSample& s) {
    std::lock_guard lock(mutex);
    samples.push_back(s);
  }, nullptr);
  client.Open();
  client.StartStreaming();
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  client.Close();
  EXPECT_EQ(::pclose(process), 0);

  const auto truth = ReadTruth(dir / "truth.csv");
  ASSERT_GE(samples.size(), 20u);
  int missing = 0;
  for (const TrackerSample& s : samples) {
    for (const BodySample& b : s.bodies) {
      const TruthRow& row = truth.at({b.frame_number, b.handle});
      EXPECT_EQ(row.status, ToString(b.ndi_status));
      if (b.has_pose) {
        EXPECT_LT((b.T_tracker_body.translation() - row.t_m).norm(), 2e-6);
      }
      missing += b.status == PoseStatus::kMissing;
    }
  }
  EXPECT_GT(missing, 0);  // dropouts arrive as MISSING, with their frame numbers
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mocap::ndi
