#pragma once
// A second consumer of the simulated camera frames besides the session writer, fed in frame order with
// what a Kinect v1 delivers. The fakenect recording writer (capture/kinect/fakenect_frame_tap.h) plugs in
// here, so that a simulated recording can be replayed through libfreenect and the capture daemon while
// the simulator itself depends on no capture driver (DESIGN.md: sim <- capture).
#include <cstdint>
#include <opencv2/core/mat.hpp>

#include "core/camera.h"

namespace mocap::sim {

class FrameTap {
 public:
  virtual ~FrameTap() = default;
  /// Called once before the first frame with the colour camera the registered depth is given in.
  virtual void Open(const PinholeCamera& color_camera) = 0;
  /// One frame: colour (8-bit BGR), registered depth (CV_32FC1, metres, 0 = none), the device's 60 MHz
  /// tick counter and the host time of the frame (seconds).
  virtual void Add(const cv::Mat& bgr, const cv::Mat& depth_m, uint64_t device_ticks, double host_time_s) = 0;
  /// After the last frame; must make the consumer's output complete.
  virtual void Close() = 0;
};

}  // namespace mocap::sim
