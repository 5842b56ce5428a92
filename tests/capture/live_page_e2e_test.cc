// The live page in a browser (docs/live-page.md): the daemon records the simulated rig (the NDI
// emulator replaying a simulated session's tracker stream, fakenect replaying its Kinect1 frames) with
// the object library, and Debian's chromium, driven by playwright-core (browser/live_page_test.js),
// opens the page, starts a session from it and checks what it shows: the counters rising, the bodies'
// states, the events of the emulator killed and restarted (done here when the script asks), and a
// thumbnail with labels. This test then labels the recorded session with `mocaplabel label` and
// compares the labels the page laid over the thumbnail with the labeller's instance image of the same
// frame, downscaled the same way (IoU per instance and over all).
#include <gtest/gtest.h>
#include <signal.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "e2e_cli.h"
#include "process.h"
#include "session/reader.h"
#include "test_dirs.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using testing::ChildProcess;
using testing::Cli;
using testing::Endpoint;

constexpr int kSimFrames = 75;  // 2.5 s at 30 Hz: long enough for the page to see the replays play

Endpoint StartReplayEmulator(const fs::path& dir, const fs::path& sim, int port, const std::string& log) {
  Endpoint e{std::make_unique<ChildProcess>(std::vector<std::string>{MOCAPLABEL_EXE, "ndi-emulator", "--replay", sim.string(),
                                                                     "--port", std::to_string(port), "--json"},
                                            std::map<std::string, std::string>{}, dir / log)};
  e.port = testing::FirstJsonLine(*e.process, "ndi-emulator")["port"];
  return e;
}

fs::path WriteRig(const fs::path& dir, int tracker_port) {
  std::ifstream in(fs::path(MOCAP_SOURCE_DIR) / "calib" / "emulator_rig.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string rig = text.str();
  const std::string shipped = "127.0.0.1:8765";
  rig.replace(rig.find(shipped), shipped.size(), "127.0.0.1:" + std::to_string(tracker_port));
  std::ofstream(dir / "rig.yaml") << rig;
  return dir / "rig.yaml";
}

struct Iou {
  double overall = 0;                 ///< summed intersections over summed unions
  std::map<std::string, double> per;  ///< by object
};

// The page's labels PNG (each instance in its legend colour) against the labeller's instance ids.
Iou CompareOverlay(const cv::Mat& overlay_bgra, const cv::Mat& instance_ids, const nlohmann::json& legend) {
  cv::Mat ids;
  cv::resize(instance_ids, ids, overlay_bgra.size(), 0, 0, cv::INTER_NEAREST);  // as the daemon downscales
  Iou iou;
  int64_t inter_all = 0, union_all = 0;
  for (const auto& entry : legend) {
    const std::string hex = entry["color"];
    const cv::Vec3b bgr(static_cast<uint8_t>(std::stoi(hex.substr(5, 2), nullptr, 16)),
                        static_cast<uint8_t>(std::stoi(hex.substr(3, 2), nullptr, 16)),
                        static_cast<uint8_t>(std::stoi(hex.substr(1, 2), nullptr, 16)));
    const uint16_t id = entry["id"];
    int64_t inter = 0, uni = 0;
    for (int r = 0; r < ids.rows; ++r) {
      for (int c = 0; c < ids.cols; ++c) {
        const cv::Vec4b p = overlay_bgra.at<cv::Vec4b>(r, c);
        const bool shown = p[3] > 0 && p[0] == bgr[0] && p[1] == bgr[1] && p[2] == bgr[2];
        const bool labelled = ids.at<uint16_t>(r, c) == id;
        inter += shown && labelled;
        uni += shown || labelled;
      }
    }
    if (uni > 0) iou.per[entry["object"]] = static_cast<double>(inter) / static_cast<double>(uni);
    inter_all += inter, union_all += uni;
  }
  iou.overall = union_all > 0 ? static_cast<double>(inter_all) / static_cast<double>(union_all) : 0.0;
  return iou;
}

// Runs the browser script, killing and restarting the emulator when it asks; its RESULT.
nlohmann::json RunBrowser(const fs::path& dir, const fs::path& sim, int daemon_port, Endpoint& emulator) {
  const std::string node = MOCAP_NODE_EXE;
  if (node.empty()) throw std::runtime_error("node was not found when the build was configured: run scripts/install-deps.sh");
  ChildProcess browser({node, (fs::path(MOCAP_SOURCE_DIR) / "tests/capture/browser/live_page_test.js").string(),
                        "http://127.0.0.1:" + std::to_string(daemon_port) + "/", dir.string()},
                       {{"NODE_PATH", MOCAP_BROWSER_NODE_MODULES}}, dir / "browser.log");
  while (const std::optional<std::string> line = browser.ReadLine(90000)) {
    if (*line == "KILL_TRACKER") {
      const int port = emulator.port;
      emulator.process->Signal(SIGKILL);
      emulator.process->Wait(5000);
      emulator = StartReplayEmulator(dir, sim, port, "emulator2.log");
    } else if (line->rfind("RESULT ", 0) == 0) {
      EXPECT_EQ(browser.Wait(30000), 0) << browser.Log();
      return nlohmann::json::parse(line->substr(7));
    }
  }
  ADD_FAILURE() << "the browser script ended without a result (exit " << browser.Wait(30000).value_or(-1) << "):\n"
                << browser.Log();
  return nullptr;
}

TEST(LivePageBrowser, ShowsTheRecordingAndItsLabelsInABrowser) {
  const fs::path dir = testing::FreshCaptureDir("live_page");
  std::ofstream(dir / "scenario.yaml") << "frame_count: " << kSimFrames << "\n";
  const fs::path sim = dir / "sim";
  ASSERT_EQ(Cli(dir, {"sim", "record", "--scenario", (dir / "scenario.yaml").string(), "--objects",
                      (fs::path(MOCAP_SOURCE_DIR) / "meshes/objects.yaml").string(), "--out", sim.string(), "--fakenect"})
                .first, 0);
  Endpoint emulator = StartReplayEmulator(dir, sim, 0, "emulator.log");
  const fs::path rig = WriteRig(dir, emulator.port);
  const fs::path objects = sim / "objects.yaml";
  Endpoint daemon = testing::StartDaemon(
      rig, {{"LD_LIBRARY_PATH", "/usr/lib/x86_64-linux-gnu/fakenect"}, {"FAKENECT_PATH", (sim / "fakenect").string()}},
      {"--port", "0", "--objects", objects.string()});

  const nlohmann::json result = RunBrowser(dir, sim, daemon.port, emulator);
  ASSERT_TRUE(result.is_object());
  const auto [stop_status, summary] = Cli(dir, {"capture", "stop", "--port", std::to_string(daemon.port)});
  ASSERT_EQ(stop_status, 0);
  std::cout << "page: " << result.dump() << "\nsession: " << summary.dump() << "\n";
  EXPECT_EQ(result["camera_dropped"], 0);
  for (const auto& [stream, counters] : summary["streams"].items()) EXPECT_EQ(counters["dropped"], 0) << stream;

  const fs::path session = dir / "sessions" / "live";
  const fs::path labels = dir / "labels";
  ASSERT_EQ(Cli(dir, {"label", session.string(), "--rig", rig.string(), "--objects", objects.string(), "--out",
                      labels.string()}).first, 0);
  const SessionReader reader = SessionReader::Open(session);
  int64_t index = -1;
  for (int64_t i = 0; i < reader.frame_count("kinect1"); ++i)
    if (reader.frame("kinect1", i).record.frame == result["frame"].get<int64_t>()) index = i;
  ASSERT_GE(index, 0) << "frame " << result["frame"] << " of the page is not in the session";
  char name[32];
  std::snprintf(name, sizeof name, "%06lld.png", static_cast<long long>(index));
  const cv::Mat instance_ids = cv::imread((labels / "kinect1" / "instance" / name).string(), cv::IMREAD_UNCHANGED);
  const cv::Mat overlay = cv::imread((dir / "overlay.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(instance_ids.type(), CV_16UC1);
  ASSERT_EQ(overlay.type(), CV_8UC4);
  const Iou iou = CompareOverlay(overlay, instance_ids, result["legend"]);
  std::cout << "overlay of frame " << result["frame"] << " against the labeller's instance image: IoU " << iou.overall;
  for (const auto& [object, value] : iou.per) std::cout << ", " << object << " " << value;
  std::cout << "\n";
  EXPECT_GE(iou.overall, 0.95);
  for (const auto& [object, value] : iou.per) EXPECT_GE(value, 0.9) << object;
  EXPECT_EQ(iou.per.size(), result["legend"].size());
}

}  // namespace
}  // namespace mocap
