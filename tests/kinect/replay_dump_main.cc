// kinect_replay_dump OUT_DIR [--tilt-interval-ms MS] [--timeout-ms MS] [--throw-at-frame N]
// Opens the first Kinect1 through whatever libfreenect the loader picked (the fakenect build when run with
// LD_LIBRARY_PATH=/usr/lib/x86_64-linux-gnu/fakenect FAKENECT_PATH=<recording>), streams until the stream
// ends, and writes every delivered frame to OUT_DIR: color_<seq>.png, depth_<seq>.png (16-bit mm) and
// frames.json (timestamps, tilt, intrinsics, stats). Exit 0 on success, 3 when the device fails to open.
// --throw-at-frame N makes the frame callback throw at frame N (to check the device ends the stream).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "capture/kinect/kinect1_device.h"

namespace {

using mocap::capture::RgbdFrame;

nlohmann::json FrameJson(const RgbdFrame& f) {
  nlohmann::json j = {{"sequence", f.sequence},
                      {"depth_ticks_raw", f.depth_ticks_raw},
                      {"color_ticks_raw", f.color_ticks_raw},
                      {"depth_ticks", f.depth_ticks},
                      {"color_ticks", f.color_ticks},
                      {"depth_device_ns", f.depth_device_ns()},
                      {"depth_host_ns", f.depth_host_ns},
                      {"color_host_ns", f.color_host_ns},
                      {"depth_registered", f.depth_registered},
                      {"intrinsics_source", f.intrinsics_source},
                      {"fx", f.depth_camera.fx},
                      {"fy", f.depth_camera.fy},
                      {"cx", f.depth_camera.cx},
                      {"cy", f.depth_camera.cy}};
  if (f.tilt) {
    j["tilt"] = {{"accel_raw", {f.tilt->accel_raw[0], f.tilt->accel_raw[1], f.tilt->accel_raw[2]}},
                 {"accel_mps2", {f.tilt->accel_mps2[0], f.tilt->accel_mps2[1], f.tilt->accel_mps2[2]}},
                 {"tilt_deg", f.tilt->tilt_deg},
                 {"tilt_status", f.tilt->tilt_status}};
  }
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: kinect_replay_dump OUT_DIR [--tilt-interval-ms MS] [--timeout-ms MS]\n");
    return 2;
  }
  const std::filesystem::path out_dir = argv[1];
  mocap::capture::Kinect1Options options;
  int timeout_ms = 20000;
  int64_t throw_at_frame = -1;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--tilt-interval-ms") options.tilt_poll_interval_ms = std::atof(argv[i + 1]);
    if (flag == "--timeout-ms") timeout_ms = std::atoi(argv[i + 1]);
    if (flag == "--throw-at-frame") throw_at_frame = std::atoll(argv[i + 1]);
  }
  std::filesystem::create_directories(out_dir);
  auto device = mocap::capture::CreateKinect1Device(options);
  try {
    device->Open();
  } catch (const mocap::capture::DeviceError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 3;
  }
  // Frames are kept in memory and written after the stream ends: slow PNG encoding in the callback
  // would delay the device thread and distort the host receive times under test.
  std::mutex mutex;
  std::vector<RgbdFrame> received;
  device->Start([&](RgbdFrame&& frame) {
    if (frame.sequence == throw_at_frame) throw std::runtime_error("stop requested by the test");
    std::lock_guard lock(mutex);
    received.push_back(std::move(frame));
  });
  const bool ended = device->WaitForStreamEnd(timeout_ms);
  device->Stop();
  const auto stats = device->stats();
  nlohmann::json frames = nlohmann::json::array();
  for (const RgbdFrame& frame : received) {
    const std::string seq = std::to_string(frame.sequence);
    cv::imwrite((out_dir / ("color_" + seq + ".png")).string(), frame.bgr);
    cv::imwrite((out_dir / ("depth_" + seq + ".png")).string(), frame.depth_mm);
    frames.push_back(FrameJson(frame));
  }
  const nlohmann::json summary = {{"frames", frames},
                                  {"stream_ended", ended},
                                  {"stream_end_reason", device->stream_end_reason().value_or("")},
                                  {"frames_delivered", stats.frames_delivered},
                                  {"depth_unpaired", stats.depth_unpaired},
                                  {"color_unpaired", stats.color_unpaired},
                                  {"counter_wraps", stats.counter_wraps}};
  device->Close();
  std::ofstream(out_dir / "frames.json") << summary.dump(2) << '\n';
  return 0;
}
