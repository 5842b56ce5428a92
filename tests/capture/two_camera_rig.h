#pragma once
// Test support: a capture daemon recording two simulated cameras (a Kinect v1 with PNG colour and a
// Kinect v2 at its full sizes with JPEG colour as it came) and a simulated tracker, with every source
// tapped, so that the session can be compared with exactly what each source handed over.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "capture/daemon/daemon.h"
#include "capture/daemon/source.h"

namespace mocap::capture::testing {

/// What a source handed over for one camera record: its numbers and the hashes of its images (the
/// JPEG's bytes as they came; pixels otherwise).
struct HandedFrame {
  CameraFrameRecord record;
  bool color_jpeg = false;
  uint64_t color_hash = 0, depth_hash = 0;
};

/// Everything the tapped sources handed over, per stream.
class SourceLog {
 public:
  void AddFrame(const CapturedFrame& frame);
  void AddSample(const CapturedSample& sample);
  std::vector<HandedFrame> Frames(const std::string& camera) const;
  std::vector<TrackerRecord> Samples(const std::string& tracker) const;

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::vector<HandedFrame>> frames_;
  std::map<std::string, std::vector<TrackerRecord>> samples_;
};

/// Wraps a source: what it pushes is logged, then passed on unchanged.
std::unique_ptr<CaptureSource> Tapped(std::unique_ptr<CaptureSource> inner, std::shared_ptr<SourceLog> log);

/// 64-bit hash of bytes, and of an image's pixels (rows in order).
uint64_t HashBytes(const void* data, size_t size);
uint64_t HashPixels(const cv::Mat& image);

struct TwoCameraResult {
  nlohmann::json summary;  ///< StopSession's
  std::filesystem::path session_dir;
  int64_t start_ns = 0, stop_ns = 0;  ///< host monotonic time around StartSession and StopSession
  std::vector<std::string> thumbnail_cameras;  ///< the live view's cameras with a thumbnail at the end
};

/// Records `seconds` from kinect1 (640x480 PNG colour + depth), kinect2 (1920x1080 JPEG + 512x424
/// depth), both 30 Hz, and a 4-body tracker at 100 Hz, through a CaptureDaemon into <root>/S.
TwoCameraResult RecordTwoCameras(const std::filesystem::path& root, double seconds, int frame_queue,
                                 std::shared_ptr<SourceLog> log);

/// RecordTwoCameras into a fresh folder `name`, then ExpectSessionMatchesSources.
TwoCameraResult RecordAndCheckTwoCameras(const std::string& name, double seconds, int frame_queue, int decode_every);

/// Checks the session against the log: for each camera a run of the handed-over frames without a gap,
/// each once and in order, with the same numbers and image content (JPEG: the same bytes; PNG: the same
/// pixels; depth: the same values); all stamps between start and stop on the host clock; a clock fit per
/// camera matching its device clock. `decode_every`: decode every n-th JPEG through the session reader.
void ExpectSessionMatchesSources(const TwoCameraResult& result, const SourceLog& log, int decode_every);

}  // namespace mocap::capture::testing
