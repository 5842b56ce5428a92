#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <optional>
#include <thread>

#include "capture/daemon/sources.h"
#include "capture/kinect/fakenect_recording.h"
#include "core/check.h"

namespace mocap::capture {

void Kinect1SourceOptions::check() const {
  if (stream.empty()) throw InputError("kinect1.stream", "is empty: name the camera stream");
  device.check();
  if (color_camera) color_camera->check();
  if (reconnect_initial_ms < 1 || reconnect_max_ms < reconnect_initial_ms)
    throw InputError("kinect1.reconnect_ms", "need 1 <= reconnect_initial_ms <= reconnect_max_ms");
}

namespace {

class Kinect1Source final : public CaptureSource {
 public:
  explicit Kinect1Source(const Kinect1SourceOptions& options) : CaptureSource(options.stream), options_(options) {
    options_.check();
    depth_camera_ = options.device.depth_camera.value_or(NominalKinect1DepthCamera());
  }
  ~Kinect1Source() override { Close(); }

  StreamInfo stream_info() const override {
    std::lock_guard lock(mutex_);
    return KinectStreamInfo({name(), "kinect1", options_.device.camera_serial, options_.color_camera.value_or(depth_camera_),
                             depth_camera_, registered_, options_.camera_body, options_.T_body_camera});
  }

  nlohmann::json device_status() const override {
    std::lock_guard lock(mutex_);
    const DeviceStats stats = device_ ? device_->stats() : DeviceStats{};
    return {{"kind", "kinect1"},
            {"replay", replay_},
            {"frames", frames_},
            {"reconnects", reconnects_},
            {"depth_unpaired", unpaired_depth_ + stats.depth_unpaired},
            {"color_unpaired", unpaired_color_ + stats.color_unpaired},
            {"intrinsics_source", intrinsics_source_},
            {"stream_ended", ended_reason_}};
  }

  // fakenect plays its recording once, from the first frames read; the daemon starts it with a session.
  bool starts_with_session() const override {
    std::lock_guard lock(mutex_);
    return replay_;
  }

 private:
  void DoOpen() override {
    const LibfreenectInfo library = ProbeLibfreenect();
    auto device = CreateKinect1Device(options_.device);
    device->Open();
    std::lock_guard lock(mutex_);
    device_ = std::move(device);
    replay_ = library.replay;
    if (replay_) TakeRecordingCamera(library.fakenect_path);
  }

  // A replay starts with the session, after its manifest is written: take the intrinsics and the
  // registration its frames will carry from the recording now, and its first depth image's ticks, the
  // origin of its schedule (mutex_ held).
  void TakeRecordingCamera(const std::string& recording) {
    for (const FakenectEntry& entry : ReadFakenectIndex(recording))
      if (entry.type == 'd') {
        replay_first_ticks_ = entry.ticks;
        break;
      }
    const std::optional<RecordingCamera> recorded = ReadRecordingCamera(recording);
    if (!recorded) return;
    registered_ = recorded->depth_registered;
    depth_camera_ = options_.device.depth_camera.value_or(recorded->depth_camera);
    intrinsics_source_ = options_.device.depth_camera ? "options" : "recording";
  }
  void DoStart(CaptureSink* sink) override {
    sink_ = sink;
    replay_start_ns_ = MonotonicNowNs();
    {
      std::lock_guard lock(mutex_);
      stop_ = false;
    }
    StartDevice();
    watcher_ = std::thread([this] { Watch(); });
  }
  void DoStop() override {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    if (watcher_.joinable()) watcher_.join();
    if (device_ && device_->state() == DeviceState::kStreaming) device_->Stop();
  }
  void DoClose() override {
    if (device_) device_->Close();
  }

  void StartDevice() {
    device_->Start([this](RgbdFrame&& frame) { OnFrame(std::move(frame)); });
  }

  void OnFrame(RgbdFrame&& frame) {
    CapturedFrame out;
    out.camera = name();
    {
      std::lock_guard lock(mutex_);
      out.record.frame = frames_++;
      depth_camera_ = options_.device.depth_camera.value_or(frame.depth_camera);
      intrinsics_source_ = frame.intrinsics_source;
      registered_ = frame.depth_registered;
    }
    out.record.device_ticks = frame.depth_ticks;
    out.record.stamp_ns = replay_ ? ReplayStampNs(frame) : frame.depth_host_ns;
    out.color = std::move(frame.bgr);
    out.depth = std::move(frame.depth_mm);
    if (gap_pending_) ReportGap(out.record);
    last_stamp_ns_ = out.record.stamp_ns;
    sink_->PushFrame(std::move(out));
  }

  // A replayed frame is stamped when it was due: the replay's start plus its device time since the
  // recording's first depth image. fakenect's sleeps run late on a busy host (30 Hz frames 50 ms
  // apart), and the receive time would shift the frame against the tracker replay started with it.
  int64_t ReplayStampNs(const RgbdFrame& frame) const {
    if (!replay_first_ticks_ || frame.ticks_per_second <= 0) return frame.depth_host_ns;
    const int64_t since_first = frame.depth_ticks - *replay_first_ticks_;
    if (since_first < 0) return frame.depth_host_ns;
    return replay_start_ns_ + std::llround(static_cast<double>(since_first) * 1e9 / frame.ticks_per_second);
  }

  void ReportGap(const CameraFrameRecord& first_after) {
    gap_pending_ = false;
    const int64_t gap_ns = first_after.stamp_ns - last_stamp_ns_;
    sink_->PushEvent({first_after.stamp_ns, "gap", name(),
                      Str("no frames for ", gap_ns * 1e-9, " s (device reopened); first frame after: ",
                          first_after.frame)});
  }

  // Waits for the stream to end by itself; then reopens the device unless it was a replay.
  void Watch() {
    while (!device_->WaitForStreamEnd(100)) {
      std::lock_guard lock(mutex_);
      if (stop_) return;
    }
    const std::string reason = device_->stream_end_reason().value_or("stream ended");
    // The end of a replay is expected, but no more frames will come: a warning, not a device error.
    sink_->PushEvent({MonotonicNowNs(), replay_ ? "warning" : "error", name(),
                      (replay_ ? "camera replay ended, no more frames: " : "camera stream ended: ") + reason});
    {
      std::lock_guard lock(mutex_);
      ended_reason_ = reason;
    }
    if (replay_ || !options_.reconnect) return;
    Reconnect();
  }

  void Reconnect() {
    int delay_ms = options_.reconnect_initial_ms;
    for (;;) {
      {
        std::unique_lock lock(mutex_);
        if (wake_.wait_for(lock, std::chrono::milliseconds(delay_ms), [&] { return stop_; })) return;
      }
      try {
        ReopenDevice();
        sink_->PushEvent({MonotonicNowNs(), "reconnect", name(), "camera reopened"});
        gap_pending_ = true;
        Watch();
        return;
      } catch (const DeviceError&) {
        delay_ms = std::min(delay_ms * 2, options_.reconnect_max_ms);
      }
    }
  }

  void ReopenDevice() {
    const DeviceStats old_stats = device_->stats();
    device_->Close();
    auto device = CreateKinect1Device(options_.device);
    device->Open();
    {
      std::lock_guard lock(mutex_);
      unpaired_depth_ += old_stats.depth_unpaired;
      unpaired_color_ += old_stats.color_unpaired;
      device_ = std::move(device);
      ++reconnects_;
      ended_reason_.clear();
    }
    StartDevice();
  }

  Kinect1SourceOptions options_;
  CaptureSink* sink_ = nullptr;
  std::unique_ptr<CameraDevice> device_;
  std::thread watcher_;
  mutable std::mutex mutex_;  // guards the fields below and device_ replacement
  std::condition_variable wake_;
  bool stop_ = false;
  bool replay_ = false;
  bool registered_ = false;
  PinholeCamera depth_camera_;
  std::string intrinsics_source_;
  std::string ended_reason_;
  int64_t frames_ = 0, reconnects_ = 0, unpaired_depth_ = 0, unpaired_color_ = 0;
  // Set before streaming (DoOpen, DoStart), read on the device thread:
  std::optional<int64_t> replay_first_ticks_;
  int64_t replay_start_ns_ = 0;
  // Device thread only (one device streams at a time):
  std::atomic<bool> gap_pending_{false};
  std::atomic<int64_t> last_stamp_ns_{0};
};

}  // namespace

std::unique_ptr<CaptureSource> CreateKinect1Source(const Kinect1SourceOptions& options) {
  return std::make_unique<Kinect1Source>(options);
}

}  // namespace mocap::capture
