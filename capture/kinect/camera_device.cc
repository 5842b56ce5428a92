#include "capture/kinect/camera_device.h"

#include <chrono>
#include <cmath>
#include <ctime>

#include "core/check.h"

namespace mocap::capture {

const char* ToString(DeviceState state) {
  switch (state) {
    case DeviceState::kCreated: return "created";
    case DeviceState::kOpen: return "open";
    case DeviceState::kStreaming: return "streaming";
    case DeviceState::kClosed: return "closed";
  }
  return "unknown";
}

int64_t RgbdFrame::depth_device_ns() const {
  MOCAP_CHECK(ticks_per_second > 0, "frame without a device clock rate");
  // Split into whole seconds and remainder so 64-bit tick counts keep ns precision.
  const auto ticks_per_s = static_cast<int64_t>(ticks_per_second);
  const int64_t seconds = depth_ticks / ticks_per_s;
  const int64_t rest = depth_ticks % ticks_per_s;
  return seconds * 1'000'000'000 + std::llround(static_cast<double>(rest) * 1e9 / ticks_per_second);
}

int64_t MonotonicNowNs() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return int64_t{now.tv_sec} * 1'000'000'000 + now.tv_nsec;
}

CameraDevice::~CameraDevice() {
  // Derived destructors call Close() while their DoStop/DoClose can still run.
  MOCAP_CHECK(state_ != DeviceState::kStreaming, "camera device '", name_, "' destroyed while streaming");
}

void CameraDevice::Open() {
  MOCAP_CHECK(state_ == DeviceState::kCreated, "Open() on ", name_, " in state ", ToString(state_));
  DoOpen();
  state_ = DeviceState::kOpen;
}

void CameraDevice::Start(FrameCallback on_frame) {
  MOCAP_CHECK(state_ == DeviceState::kOpen, "Start() on ", name_, " in state ", ToString(state_));
  MOCAP_CHECK(on_frame != nullptr, "Start() without a frame callback");
  {
    std::lock_guard lock(mutex_);
    on_frame_ = std::move(on_frame);
    stats_ = {};
    end_reason_.reset();
  }
  DoStart();
  state_ = DeviceState::kStreaming;
}

void CameraDevice::Stop() {
  MOCAP_CHECK(state_ == DeviceState::kStreaming, "Stop() on ", name_, " in state ", ToString(state_));
  DoStop();
  state_ = DeviceState::kOpen;
}

void CameraDevice::Close() {
  if (state_ == DeviceState::kClosed) return;
  if (state_ == DeviceState::kStreaming) Stop();
  if (state_ == DeviceState::kOpen) DoClose();
  state_ = DeviceState::kClosed;
}

DeviceStats CameraDevice::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

std::optional<std::string> CameraDevice::stream_end_reason() const {
  std::lock_guard lock(mutex_);
  return end_reason_;
}

bool CameraDevice::WaitForStreamEnd(int timeout_ms) const {
  std::unique_lock lock(mutex_);
  return ended_.wait_for(lock, std::chrono::milliseconds(timeout_ms), [&] { return end_reason_.has_value(); });
}

void CameraDevice::Deliver(RgbdFrame&& frame) {
  FrameCallback callback;
  {
    std::lock_guard lock(mutex_);
    frame.sequence = stats_.frames_delivered++;
    callback = on_frame_;
  }
  callback(std::move(frame));
}

void CameraDevice::ReportStreamEnd(const std::string& reason) {
  {
    std::lock_guard lock(mutex_);
    end_reason_ = reason;
  }
  ended_.notify_all();
}

void CameraDevice::SetStreamCounts(int64_t depth_unpaired, int64_t color_unpaired, int64_t counter_wraps) {
  std::lock_guard lock(mutex_);
  stats_.depth_unpaired = depth_unpaired;
  stats_.color_unpaired = color_unpaired;
  stats_.counter_wraps = counter_wraps;
}

}  // namespace mocap::capture
