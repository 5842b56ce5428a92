#pragma once
// Builds fakenect recordings from the real Kinect1 frames of TUM RGB-D fr1/desk (9 colour + 9 depth PNGs,
// depth registered to colour, 5000 units per metre) for the replay tests. Test support only.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "capture/kinect/camera_device.h"

namespace mocap::testing {

std::filesystem::path TumDeskDir();

struct TumFrame {
  cv::Mat bgr;           ///< CV_8UC3
  cv::Mat depth_m;       ///< CV_32FC1 metres, 0 = no data
  double depth_stamp_s;  ///< TUM timestamp of the depth image (host seconds of the original recording)
};

/// The 9 frames, colour i paired with depth i (both lists are consecutive in the sequence).
std::vector<TumFrame> LoadTumDesk();

struct RecordedFrame {
  uint64_t ticks;  ///< unwrapped device ticks written (the file carries them modulo 2^32)
  double host_time_s;
};

/// Writes the frames into `dir` with device ticks first_ticks + (t - t0) * 60 MHz and host times t
/// (the TUM stamps). `tilts`, when not empty, gives one accelerometer sample per frame.
std::vector<RecordedFrame> WriteTumRecording(const std::filesystem::path& dir, const std::vector<TumFrame>& frames,
                                             uint64_t first_ticks,
                                             const std::vector<capture::TiltSample>& tilts = {});

/// A fresh empty directory under the build tree.
std::filesystem::path FreshDir(const std::string& name);

}  // namespace mocap::testing
