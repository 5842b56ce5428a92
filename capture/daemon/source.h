#pragma once
// Producers of the capture pipeline. A CaptureSource is a device (or a simulated one) that pushes
// camera frames, tracker samples and events into a CaptureSink from its own thread. The same sink
// interface is what the daemon, a Recorder used in process (src/sim's simulated rig) and the benchmark
// feed, so every producer goes through the same queues and session writer.
//
// Template method with explicit states (as PlusLib's devices and libfreenect2):
//   Created --Open--> Open --Start--> Streaming --Stop--> Open --Close--> Closed
// Open() throws capture::DeviceError (device absent or refusing) or InputError (bad options); a
// transition from the wrong state is a bug and aborts. Close() may be called in any state.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <opencv2/core/mat.hpp>
#include <string>
#include <variant>
#include <vector>

#include "capture/kinect/camera_device.h"
#include "session/manifest.h"
#include "session/records.h"

namespace mocap::capture {

/// One camera record with its images, as handed to the session writer. Colour is either `color`
/// (CV_8UC3 BGR, encoded by the writer) or `color_jpeg` (JPEG as the device sent it, a Kinect v2's:
/// stored byte for byte, never decoded on the recording path), or neither; `depth` is CV_16UC1 in the
/// stream's depth_unit_m or CV_32FC1 metres (or empty). A record carries at least one image.
struct CapturedFrame {
  std::string camera;  ///< stream name (CameraStreamInfo::name)
  CameraFrameRecord record;
  cv::Mat color, depth;
  std::shared_ptr<const std::vector<uint8_t>> color_jpeg{};  ///< shared: the live view keeps a reference
  bool has_color() const { return !color.empty() || (color_jpeg && !color_jpeg->empty()); }
};

/// One body of one tracker frame.
struct CapturedSample {
  std::string tracker;  ///< stream name (TrackerStreamInfo::name)
  TrackerRecord record;
  int markers = -1;     ///< markers the tracker measured on the body (for the live page; not recorded), -1 unknown
};

/// Where sources deliver. Implementations must not block for long: device threads call them.
class CaptureSink {
 public:
  virtual ~CaptureSink() = default;
  virtual void PushFrame(CapturedFrame&& frame) = 0;
  virtual void PushSample(CapturedSample&& sample) = 0;
  virtual void PushEvent(EventRecord&& event) = 0;
};

/// The stream a source feeds, for the session manifest: exactly one of the two.
using StreamInfo = std::variant<CameraStreamInfo, TrackerStreamInfo>;

/// Adds a source's stream to a manifest (cameras[] or trackers[]).
void AddStream(SessionManifest& manifest, const StreamInfo& info);

class CaptureSource {
 public:
  virtual ~CaptureSource();
  CaptureSource(const CaptureSource&) = delete;
  CaptureSource& operator=(const CaptureSource&) = delete;

  /// Created -> Open. Throws DeviceError / InputError; the state then stays Created.
  void Open();
  /// Open -> Streaming. `sink` must outlive the streaming (until Stop() or Close() returns).
  void Start(CaptureSink* sink);
  /// Streaming -> Open; returns once the source's thread delivers nothing more.
  void Stop();
  /// Any state -> Closed. Idempotent.
  void Close();

  DeviceState state() const { return state_.load(); }
  const std::string& name() const { return name_; }
  /// The manifest entry of the stream. Valid after Open(); may be refined by the first frames (a
  /// Kinect's intrinsics come with its frames), so a session takes it when it starts.
  virtual StreamInfo stream_info() const = 0;
  /// Device-specific counters for `status` (CRC errors, reconnects, unpaired images, ...).
  virtual nlohmann::json device_status() const = 0;
  /// True for a replay (a fakenect camera, an NDI emulator replaying a session): CaptureDaemon opens it
  /// at once but starts it with the first session, so the recording plays from its start into that
  /// session. Live devices stream from the daemon's start. Valid after Open().
  virtual bool starts_with_session() const { return false; }

 protected:
  explicit CaptureSource(std::string name) : name_(std::move(name)) {}

 private:
  virtual void DoOpen() = 0;
  virtual void DoStart(CaptureSink* sink) = 0;
  virtual void DoStop() = 0;
  virtual void DoClose() = 0;

  std::string name_;
  std::atomic<DeviceState> state_{DeviceState::kCreated};
  std::mutex transition_mutex_;
};

}  // namespace mocap::capture
