#pragma once
// The camera device interface of the capture daemon (PlusLib-style template method, libfreenect2-style
// explicit states). Public Open/Start/Stop/Close do the state bookkeeping and call the private virtual
// DoOpen/DoStart/DoStop/DoClose. Frames reach the caller through a callback on the device's own thread.
//
//   Created --Open--> Open --Start--> Streaming --Stop--> Open --Close--> Closed
//   (Close from any state stops first; calling a transition from the wrong state is a bug and aborts.)
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"

namespace mocap::capture {

enum class DeviceState { kCreated, kOpen, kStreaming, kClosed };
const char* ToString(DeviceState state);

/// A device that cannot be opened or started (not attached, busy, USB error). Expected at runtime, so
/// the daemon catches it and reports it; the message names the device and what would fix it.
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Accelerometer and tilt-motor reading of the Kinect1 motor subdevice.
struct TiltSample {
  int16_t accel_raw[3] = {0, 0, 0};  ///< counts, 819 per g (FREENECT_COUNTS_PER_G), device x y z
  double accel_mps2[3] = {0, 0, 0};  ///< m/s^2, same axes
  double tilt_deg = 0.0;             ///< motor angle against the horizon (raw encoder / 2)
  int tilt_status = 0;               ///< freenect_tilt_status_code: 0 stopped, 1 at limit, 4 moving
  int64_t host_ns = 0;               ///< CLOCK_MONOTONIC when it was read
};

/// One colour + depth pair as delivered to the daemon. Device units are converted here, at the edge.
struct RgbdFrame {
  int64_t sequence = 0;  ///< 0-based count of frames delivered since Start()
  cv::Mat bgr;           ///< CV_8UC3 (Kinect1 640x480, Kinect2 1920x1080), or empty with color_jpeg
  /// Kinect2 colour as the device sent it (JPEG), where libfreenect2 hands it over undecoded (a pipeline
  /// with its DumpRgbPacketProcessor: Frame::Raw); then `bgr` is empty and nothing decodes it here.
  std::shared_ptr<const std::vector<uint8_t>> color_jpeg{};
  cv::Mat depth_mm;      ///< CV_16UC1 millimetres, 0 = no value (Kinect1 640x480, Kinect2 512x424)
  bool depth_registered = false;  ///< depth pixel (u, v) belongs to colour pixel (u, v)
  /// Intrinsics of the image depth_mm is in (the colour camera when registered). Where they come from
  /// is in intrinsics_source ("device", "recording", "options", "nominal").
  PinholeCamera depth_camera;
  std::string intrinsics_source;

  uint32_t depth_ticks_raw = 0;  ///< device counter as the device sent it
  uint32_t color_ticks_raw = 0;
  int64_t depth_ticks = 0;       ///< the same, unwrapped (core CounterUnwrapper)
  int64_t color_ticks = 0;
  double ticks_per_second = 0;   ///< Kinect1 60e6, Kinect2 8000 (0.125 ms)
  int64_t depth_host_ns = 0;     ///< CLOCK_MONOTONIC when the depth image reached the callback
  int64_t color_host_ns = 0;
  std::optional<TiltSample> tilt;  ///< latest accelerometer reading, when the device has one

  /// Unwrapped device time of the depth image in ns (ticks converted with ticks_per_second).
  int64_t depth_device_ns() const;
};

/// Counters a device keeps while streaming (read at any time).
struct DeviceStats {
  int64_t frames_delivered = 0;
  int64_t depth_unpaired = 0;  ///< depth images dropped for lack of a colour image within tolerance
  int64_t color_unpaired = 0;
  int64_t counter_wraps = 0;   ///< device counter wraps seen (depth stream)
};

class CameraDevice {
 public:
  using FrameCallback = std::function<void(RgbdFrame&& frame)>;

  virtual ~CameraDevice();
  CameraDevice(const CameraDevice&) = delete;
  CameraDevice& operator=(const CameraDevice&) = delete;

  /// Created -> Open. Throws DeviceError when the device cannot be opened (the state stays Created).
  void Open();
  /// Open -> Streaming; `on_frame` runs on the device thread and must not block for long. If it throws,
  /// the stream ends and stream_end_reason() holds the exception's message.
  void Start(FrameCallback on_frame);
  /// Streaming -> Open; returns after the device thread has delivered its last frame.
  void Stop();
  /// Any state -> Closed. Idempotent.
  void Close();

  DeviceState state() const { return state_.load(); }
  const std::string& name() const { return name_; }
  DeviceStats stats() const;

  /// Set when the stream ended by itself (end of a replay, device unplugged): why. Frames stop then.
  std::optional<std::string> stream_end_reason() const;
  /// Waits until the stream ends by itself or `timeout_ms` passes; true when it ended.
  bool WaitForStreamEnd(int timeout_ms) const;

 protected:
  explicit CameraDevice(std::string name) : name_(std::move(name)) {}
  /// For the device thread: stamps the sequence number and calls the callback.
  void Deliver(RgbdFrame&& frame);
  void ReportStreamEnd(const std::string& reason);
  /// Totals so far of images dropped for lack of a partner, and counter wraps seen.
  void SetStreamCounts(int64_t depth_unpaired, int64_t color_unpaired, int64_t counter_wraps);

 private:
  virtual void DoOpen() = 0;
  virtual void DoStart() = 0;
  virtual void DoStop() = 0;
  virtual void DoClose() = 0;

  std::string name_;
  std::atomic<DeviceState> state_{DeviceState::kCreated};
  FrameCallback on_frame_;
  mutable std::mutex mutex_;
  mutable std::condition_variable ended_;
  DeviceStats stats_;
  std::optional<std::string> end_reason_;
};

/// CLOCK_MONOTONIC now, in ns.
int64_t MonotonicNowNs();

}  // namespace mocap::capture
