#pragma once
// Recordings in the on-disk format of libfreenect 0.5.3's fakenect (fakenect/record.c), which the
// fakenect build of libfreenect replays when FAKENECT_PATH names the directory:
//   INDEX.txt                       one file name per line, in replay order
//   d-<host s %.6f>-<ticks>.pgm     "P5 640 480 65535\n" + 640x480 little-endian uint16 raw 11-bit disparity
//   r-<host s %.6f>-<ticks>.ppm     "P6 640 480 255\n" + 640x480x3 bytes RGB
//   a-<host s %.6f>-<ticks>.dump    a freenect_raw_tilt_state struct (accelerometer + tilt motor)
// <ticks> is the device's 32-bit 60 MHz counter. Replay sleeps to reproduce the host-time spacing.
// Depth is stored as raw disparity (fakenect 0.5.3 replays nothing else), converted from metres with the
// inverse of the fit in kinect1_depth.h. Next to it, mocap_camera.json (ignored by libfreenect) keeps
// the intrinsics of the depth image and whether it is registered to colour.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "capture/kinect/camera_device.h"

namespace mocap::capture {

inline constexpr int kFakenectWidth = 640;
inline constexpr int kFakenectHeight = 480;
inline constexpr const char* kRecordingCameraFile = "mocap_camera.json";

/// What the camera that made a recording looked like; written to mocap_camera.json.
struct RecordingCamera {
  PinholeCamera depth_camera;     ///< intrinsics of the depth image
  bool depth_registered = false;  ///< depth pixels aligned with colour pixels
};

/// Per-frame outcome of the depth conversion.
struct FakenectFrameStats {
  int64_t depth_valid = 0;          ///< pixels written with a depth
  int64_t depth_no_value = 0;       ///< pixels that had no depth (0) in the input
  int64_t depth_unrepresentable = 0;  ///< pixels with a depth outside 0.30..10 m, written as "no value"
};

class FakenectRecordingWriter {
 public:
  /// Creates `dir` if needed. Throws InputError when it already holds an INDEX.txt (as fakenect-record
  /// refuses) or cannot be written.
  explicit FakenectRecordingWriter(const std::filesystem::path& dir,
                                   std::optional<RecordingCamera> camera = std::nullopt);
  ~FakenectRecordingWriter();
  FakenectRecordingWriter(const FakenectRecordingWriter&) = delete;
  FakenectRecordingWriter& operator=(const FakenectRecordingWriter&) = delete;

  /// Appends one frame (and, when given, an accelerometer sample replayed just before it).
  /// bgr: CV_8UC3 640x480 (OpenCV channel order; written as RGB). depth: 640x480, CV_16UC1 in mm or
  /// CV_32FC1 / CV_64FC1 in metres; 0 = no value. device_ticks: the 60 MHz counter (taken modulo 2^32,
  /// so unwrapped counts may be passed). host_time_s: non-decreasing; replay reproduces its spacing.
  /// Throws InputError naming the frame index on a wrong size or type, or a host time going backwards.
  FakenectFrameStats AddFrame(const cv::Mat& bgr, const cv::Mat& depth, uint64_t device_ticks,
                              double host_time_s, const std::optional<TiltSample>& tilt = std::nullopt);
  /// Flushes INDEX.txt and writes mocap_camera.json. Idempotent; the destructor calls it.
  void Close();

  int frames() const { return frames_; }
  const FakenectFrameStats& totals() const { return totals_; }

 private:
  std::string WriteFile(char type, double host_time_s, uint32_t ticks, const std::string& extension,
                        const std::string& header, const void* data, size_t bytes);

  std::filesystem::path dir_;
  std::optional<RecordingCamera> camera_;
  std::ofstream index_;
  int frames_ = 0;
  double last_host_time_s_ = -1.0;
  FakenectFrameStats totals_;
};

/// One INDEX.txt line.
struct FakenectEntry {
  char type = 0;  ///< 'd', 'r' or 'a'
  double host_time_s = 0;
  uint32_t ticks = 0;
  std::filesystem::path file;
};

/// Reads INDEX.txt; throws InputError naming INDEX.txt:line for a malformed line or a missing file.
std::vector<FakenectEntry> ReadFakenectIndex(const std::filesystem::path& dir);
/// Raw 11-bit disparity (CV_16UC1) of a 'd' file; throws InputError on a bad header or size.
cv::Mat ReadFakenectDepthRaw(const std::filesystem::path& file);
/// Colour (CV_8UC3, BGR) of an 'r' file; throws InputError on a bad header or size.
cv::Mat ReadFakenectColorBgr(const std::filesystem::path& file);
/// mocap_camera.json of a recording, when present; throws InputError when it is malformed.
std::optional<RecordingCamera> ReadRecordingCamera(const std::filesystem::path& dir);

}  // namespace mocap::capture
