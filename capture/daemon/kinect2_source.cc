// The daemon's Kinect2 source (sources.h) and the camera choice of the rig's capture: section.
#include <atomic>
#include <cmath>
#include <mutex>
#include <thread>
#include <opencv2/imgcodecs.hpp>

#include "capture/daemon/sources.h"
#include "core/check.h"

namespace mocap::capture {

void Kinect2SourceOptions::check() const {
  if (stream.empty()) throw InputError("kinect2.stream", "is empty: name the camera stream");
  device.check();
  if (color_camera) color_camera->check();
  if (jpeg_quality < 1 || jpeg_quality > 100) throw InputError("kinect2.jpeg_quality", "must be in 1..100");
}

namespace {

// Until the first frame brings the device's factory values: typical Kinect v2 values (colour 1081.37 px
// focal length at 1920x1080, the ToF camera 365.456 px at 512x424), which the manifest would otherwise
// leave zero.
const PinholeCamera kNominalColor{1920, 1080, 1081.37, 1081.37, 959.5, 539.5, {}};
const PinholeCamera kNominalDepth{512, 424, 365.456, 365.456, 254.878, 205.395, {}};

class Kinect2Source final : public CaptureSource {
 public:
  explicit Kinect2Source(const Kinect2SourceOptions& options) : CaptureSource(options.stream), options_(options) {
    options_.check();
  }
  ~Kinect2Source() override { Close(); }

  StreamInfo stream_info() const override {
    std::lock_guard lock(mutex_);
    const PinholeCamera color = options_.color_camera.value_or(color_from_device_.value_or(kNominalColor));
    return KinectStreamInfo({name(), "kinect2", options_.device.serial, color, registered_ ? color : depth_camera_,
                             registered_, options_.camera_body, options_.T_body_camera});
  }

  nlohmann::json device_status() const override {
    std::lock_guard lock(mutex_);
    return {{"kind", "kinect2"}, {"frames", frames_}, {"jpeg_as_sent", jpeg_as_sent_},
            {"jpeg_encoded", jpeg_encoded_}, {"stream_ended", ended_reason_}};
  }

 private:
  void DoOpen() override {
    device_ = CreateKinect2Device(options_.device);  // DeviceError where libfreenect2 was not built
    device_->Open();
  }
  void DoStart(CaptureSink* sink) override {
    sink_ = sink;
    device_->Start([this](RgbdFrame&& frame) { OnFrame(std::move(frame)); });
    watcher_ = std::thread([this] { Watch(); });
  }
  void DoStop() override {
    stop_ = true;
    if (watcher_.joinable()) watcher_.join();
    if (device_->state() == DeviceState::kStreaming) device_->Stop();
  }
  void DoClose() override {
    if (device_) device_->Close();
  }

  void OnFrame(RgbdFrame&& frame) {
    CapturedFrame out;
    out.camera = name();
    out.record.device_ticks = frame.color_ticks;
    out.record.stamp_ns = frame.color_host_ns;
    // libfreenect2 pairs a depth image with the colour image after it; their device timestamps say how
    // far apart they were exposed (about 15 ms), which a check of moving objects against the depth needs.
    if (frame.ticks_per_second > 0 && frame.depth_ticks != frame.color_ticks)
      out.record.depth_stamp_ns = frame.color_host_ns - std::llround(static_cast<double>(frame.color_ticks - frame.depth_ticks) *
                                                                     1e9 / frame.ticks_per_second);
    const bool as_sent = frame.color_jpeg != nullptr;
    if (as_sent) {
      out.color_jpeg = std::move(frame.color_jpeg);
    } else if (!frame.bgr.empty()) {
      auto jpeg = std::make_shared<std::vector<uint8_t>>();
      MOCAP_CHECK(cv::imencode(".jpg", frame.bgr, *jpeg, {cv::IMWRITE_JPEG_QUALITY, options_.jpeg_quality}), "JPEG encoding failed");
      out.color_jpeg = std::move(jpeg);
    }
    out.depth = std::move(frame.depth_mm);
    {
      std::lock_guard lock(mutex_);
      out.record.frame = frames_++;
      if (out.color_jpeg) ++(as_sent ? jpeg_as_sent_ : jpeg_encoded_);
      // Registered depth lies in the colour camera, whose factory intrinsics it then carries.
      registered_ = frame.depth_registered;
      if (registered_) color_from_device_ = frame.depth_camera;
      else depth_camera_ = frame.depth_camera;
    }
    sink_->PushFrame(std::move(out));
  }

  void Watch() {
    while (!stop_ && !device_->WaitForStreamEnd(100)) {
    }
    if (stop_) return;
    const std::string reason = device_->stream_end_reason().value_or("stream ended");
    sink_->PushEvent({MonotonicNowNs(), "error", name(), "camera stream ended (not reopened): " + reason});
    std::lock_guard lock(mutex_);
    ended_reason_ = reason;
  }

  Kinect2SourceOptions options_;
  CaptureSink* sink_ = nullptr;
  std::unique_ptr<CameraDevice> device_;
  std::thread watcher_;
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;  // guards the fields below
  std::optional<PinholeCamera> color_from_device_;
  PinholeCamera depth_camera_ = kNominalDepth;
  bool registered_ = false;
  int64_t frames_ = 0, jpeg_as_sent_ = 0, jpeg_encoded_ = 0;
  std::string ended_reason_;
};

}  // namespace

CameraStreamInfo KinectStreamInfo(const KinectStream& kinect) {
  CameraStreamInfo info;
  info.name = kinect.name;
  info.model = kinect.model;
  info.serial = kinect.serial;
  info.color_camera = kinect.color_camera;
  info.depth_camera = kinect.depth_camera;
  info.depth_registered_to_color = kinect.registered;
  info.depth_unit_m = 0.001;  // RgbdFrame::depth_mm
  info.camera_body = kinect.camera_body;
  info.T_body_camera = kinect.T_body_camera;
  return info;
}

std::unique_ptr<CaptureSource> CreateKinect2Source(const Kinect2SourceOptions& options) {
  return std::make_unique<Kinect2Source>(options);
}

const std::string& StreamOf(const CameraSourceOptions& camera) {
  return std::visit([](const auto& c) -> const std::string& { return c.stream; }, camera);
}

std::unique_ptr<CaptureSource> CreateCameraSource(const CameraSourceOptions& camera) {
  if (const auto* k1 = std::get_if<Kinect1SourceOptions>(&camera)) return CreateKinect1Source(*k1);
  return CreateKinect2Source(std::get<Kinect2SourceOptions>(camera));
}

void SetCalibration(CameraSourceOptions& camera, const std::optional<PinholeCamera>& color_camera,
                    const std::string& camera_body, const Rigid3d& T_body_camera) {
  std::visit(
      [&](auto& c) {
        c.color_camera = color_camera;
        c.camera_body = camera_body;
        c.T_body_camera = T_body_camera;
      },
      camera);
}

}  // namespace mocap::capture
