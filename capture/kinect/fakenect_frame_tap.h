#pragma once
// The simulator's frame tap (src/sim/record/frame_tap.h) writing a libfreenect fakenect recording, so that
// `mocaplabel sim record --fakenect` produces a folder that FAKENECT_PATH replays through the real
// libfreenect client (docs/kinect.md).
#include <filesystem>
#include <memory>

#include "capture/kinect/fakenect_recording.h"
#include "sim/record/frame_tap.h"

namespace mocap::capture {

class FakenectFrameTap final : public sim::FrameTap {
 public:
  /// Precondition: `dir` does not exist or is empty (the writer creates it on Open).
  explicit FakenectFrameTap(std::filesystem::path dir) : dir_(std::move(dir)) {}
  void Open(const PinholeCamera& color_camera) override {
    writer_ = std::make_unique<FakenectRecordingWriter>(dir_, RecordingCamera{color_camera, true});
  }
  void Add(const cv::Mat& bgr, const cv::Mat& depth_m, uint64_t device_ticks, double host_time_s) override {
    writer_->AddFrame(bgr, depth_m, device_ticks, host_time_s);
  }
  void Close() override {
    if (writer_) writer_->Close();
  }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::unique_ptr<FakenectRecordingWriter> writer_;
};

}  // namespace mocap::capture
