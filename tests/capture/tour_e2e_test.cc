// The tour of docs/capture.md, "Recording without hardware", run as written: a simulated session, the
// NDI emulator replaying its tracker, the daemon with calib/emulator_rig.yaml and a fakenect camera,
// capture start / status / stop, info, and label with meshes/objects.yaml. The commands come from the
// doc itself (tour_runner.h); only the work folder and the tracker port (a free one for 8765) differ.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "session/reader.h"
#include "test_dirs.h"
#include "tour_runner.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

int FreeTcpPort() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof(address);
  ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address));
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  ::close(fd);
  return ntohs(address.sin_port);
}

void ExpectSessionRecordedTheReplays(const fs::path& session) {
  const SessionReader reader = SessionReader::Open(session);
  EXPECT_TRUE(reader.complete());
  EXPECT_GE(reader.frame_count("kinect1"), 20) << "the fakenect replay started with `capture start`";
  const TrackerStreamInfo* ndi = reader.manifest().FindTracker("ndi");
  ASSERT_NE(ndi, nullptr);
  EXPECT_EQ(ndi->bodies, (std::vector<std::string>{"camera_body", "table_body", "engine_body", "funnel_body", "bottle_body"}));
  for (const std::string& body : ndi->bodies) {
    int64_t with_pose = 0;
    for (const TrackerRecord& r : reader.BodyRecords("ndi", body)) with_pose += HasPose(r.status);
    EXPECT_GT(with_pose, 30) << body << ": the emulator's replay started with the session";
  }
  for (const EventRecord& e : reader.events()) EXPECT_NE(e.kind, "error") << e.stream << ": " << e.detail;
}

// The simulation's truth, T_camera_mesh translations by (sim frame index, object name).
std::map<std::pair<int64_t, std::string>, Eigen::Vector3d> TruthTranslations(const fs::path& sim) {
  std::map<std::pair<int64_t, std::string>, Eigen::Vector3d> truth;
  std::ifstream poses(sim / "truth" / "poses.jsonl");
  for (std::string line; std::getline(poses, line);) {
    const nlohmann::json frame = nlohmann::json::parse(line);
    for (const auto& object : frame["objects"]) {
      const std::vector<double> t = object["T_camera_mesh"]["t_m"];
      truth[{frame["index"].get<int64_t>(), object["name"].get<std::string>()}] = {t[0], t[1], t[2]};
    }
  }
  return truth;
}

// Labels of the recorded session against the simulation they replay (the same frame by its device
// ticks): the camera and tracker replays started together, so the poses agree to a few mm (a replay
// shifted by 0.5 s, as before the replays started with the session, is off by centimetres).
void ExpectLabelsMatchTheSimulation(const fs::path& labels, const fs::path& session, const fs::path& sim) {
  std::ifstream manifest_file(labels / "label_manifest.json");
  ASSERT_TRUE(manifest_file) << "no label output";
  EXPECT_EQ(nlohmann::json::parse(manifest_file).value("complete", false), true);
  const SessionReader recorded = SessionReader::Open(session), simulated = SessionReader::Open(sim);
  std::map<int64_t, int64_t> sim_frame_of_ticks;
  for (int64_t i = 0; i < simulated.frame_count("kinect1"); ++i) sim_frame_of_ticks[simulated.frame("kinect1", i).record.device_ticks] = i;
  const auto truth = TruthTranslations(sim);
  std::vector<double> errors_m;
  int64_t total = 0, missing_body = 0;
  std::ifstream records(labels / "labels.jsonl");
  for (std::string line; std::getline(records, line); ++total) {
    const nlohmann::json r = nlohmann::json::parse(line);
    missing_body += r["flags"].dump().find("missing_body") != std::string::npos;
    if (!r.contains("t_m")) continue;  // a tracker gap on a loaded host
    const int64_t ticks = recorded.frame("kinect1", r["index"].get<int64_t>()).record.device_ticks;
    const std::vector<double> t = r["t_m"];
    errors_m.push_back((Eigen::Vector3d(t[0], t[1], t[2]) - truth.at({sim_frame_of_ticks.at(ticks), r["name"]})).norm());
  }
  EXPECT_EQ(missing_body, 0) << "the objects' bodies were not found";
  ASSERT_GT(errors_m.size(), static_cast<size_t>(total) / 2) << "most records have a pose";
  std::nth_element(errors_m.begin(), errors_m.begin() + static_cast<std::ptrdiff_t>(errors_m.size() / 2), errors_m.end());
  EXPECT_LT(errors_m[errors_m.size() / 2], 0.005) << "median label error against the simulation's truth";
}

TEST(CaptureTour, TheDocumentedCommandsRecordAndLabelASessionWithoutHardware) {
  const fs::path work = testing::FreshCaptureDir("tour");
  fs::create_directories(work / "logs");
  fs::current_path(MOCAP_SOURCE_DIR);  // the tour runs in the checkout: calib/, meshes/
  const std::string port = std::to_string(FreeTcpPort());
  testing::TourRunner tour({.mocaplabel = MOCAPLABEL_EXE,
                            .variables = {{"T", (work / "T").string()}},
                            .replace = {{"--port 8765", "--port " + port}, {"127.0.0.1:8765", "127.0.0.1:" + port}},
                            .files = {work / "T" / "rig.yaml"},
                            .log_dir = work / "logs"});
  const std::vector<std::string> commands =
      testing::ReadTourCommands(fs::path(MOCAP_SOURCE_DIR) / "docs" / "capture.md", "<!-- tour:");
  for (const std::string& command : commands) {
    try {
      tour.Run(command);
    } catch (const std::exception& e) {
      FAIL() << "docs/capture.md tour: " << e.what();
    }
  }
  ExpectSessionRecordedTheReplays(work / "T" / "sessions" / "tour");
  ExpectLabelsMatchTheSimulation(work / "T" / "labels", work / "T" / "sessions" / "tour", work / "T" / "sim");
}

}  // namespace
}  // namespace mocap
