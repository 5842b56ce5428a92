#include "capture/daemon/source.h"

#include "core/check.h"

namespace mocap::capture {

void AddStream(SessionManifest& manifest, const StreamInfo& info) {
  if (const auto* camera = std::get_if<CameraStreamInfo>(&info)) manifest.cameras.push_back(*camera);
  else manifest.trackers.push_back(std::get<TrackerStreamInfo>(info));
}

CaptureSource::~CaptureSource() = default;

void CaptureSource::Open() {
  std::lock_guard lock(transition_mutex_);
  MOCAP_CHECK(state_ == DeviceState::kCreated, name_, ": Open() in state ", ToString(state_.load()));
  DoOpen();
  state_ = DeviceState::kOpen;
}

void CaptureSource::Start(CaptureSink* sink) {
  std::lock_guard lock(transition_mutex_);
  MOCAP_CHECK(state_ == DeviceState::kOpen, name_, ": Start() in state ", ToString(state_.load()));
  MOCAP_CHECK(sink != nullptr, name_, ": Start() without a sink");
  DoStart(sink);
  state_ = DeviceState::kStreaming;
}

void CaptureSource::Stop() {
  std::lock_guard lock(transition_mutex_);
  MOCAP_CHECK(state_ == DeviceState::kStreaming, name_, ": Stop() in state ", ToString(state_.load()));
  DoStop();
  state_ = DeviceState::kOpen;
}

void CaptureSource::Close() {
  std::lock_guard lock(transition_mutex_);
  if (state_ == DeviceState::kClosed) return;
  if (state_ == DeviceState::kStreaming) DoStop();
  if (state_ != DeviceState::kCreated) DoClose();
  state_ = DeviceState::kClosed;
}

}  // namespace mocap::capture
