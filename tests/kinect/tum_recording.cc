#include "tum_recording.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "capture/kinect/fakenect_recording.h"
#include "core/check.h"

namespace mocap::testing {
namespace fs = std::filesystem;

fs::path TumDeskDir() { return fs::path(MOCAP_SHARED_DIR) / "realdata" / "tum_fr1_desk_9frames"; }

namespace {

std::vector<fs::path> SortedPngs(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().extension() == ".png") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

std::vector<TumFrame> LoadTumDesk() {
  const auto colors = SortedPngs(TumDeskDir() / "rgb");
  const auto depths = SortedPngs(TumDeskDir() / "depth");
  MOCAP_CHECK(colors.size() == 9 && depths.size() == 9, "TUM fr1/desk sample is incomplete");
  std::vector<TumFrame> frames;
  for (size_t i = 0; i < colors.size(); ++i) {
    TumFrame frame;
    frame.bgr = cv::imread(colors[i].string(), cv::IMREAD_COLOR);
    const cv::Mat depth_png = cv::imread(depths[i].string(), cv::IMREAD_ANYDEPTH);
    MOCAP_CHECK(!frame.bgr.empty() && depth_png.type() == CV_16UC1, "cannot read ", colors[i], " / ", depths[i]);
    depth_png.convertTo(frame.depth_m, CV_32FC1, 1.0 / 5000.0);  // TUM: 5000 units per metre
    frame.depth_stamp_s = std::stod(depths[i].stem().string());
    frames.push_back(std::move(frame));
  }
  return frames;
}

std::vector<RecordedFrame> WriteTumRecording(const fs::path& dir, const std::vector<TumFrame>& frames,
                                             uint64_t first_ticks, const std::vector<capture::TiltSample>& tilts) {
  // TUM recommends fx = fy = 525, cx = 319.5, cy = 239.5 for its registered depth.
  const capture::RecordingCamera camera{PinholeCamera{640, 480, 525.0, 525.0, 319.5, 239.5, {}}, true};
  capture::FakenectRecordingWriter writer(dir, camera);
  std::vector<RecordedFrame> recorded;
  const double t0 = frames.front().depth_stamp_s;
  for (size_t i = 0; i < frames.size(); ++i) {
    const double t = frames[i].depth_stamp_s;
    const uint64_t ticks = first_ticks + static_cast<uint64_t>(std::llround((t - t0) * 60e6));
    std::optional<capture::TiltSample> tilt;
    if (!tilts.empty()) tilt = tilts[i];
    writer.AddFrame(frames[i].bgr, frames[i].depth_m, ticks, t, tilt);
    recorded.push_back({ticks, t});
  }
  writer.Close();
  return recorded;
}

fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::path(MOCAP_BINARY_DIR) / "test_output" / "kinect" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace mocap::testing
