#include <cmath>
#include <thread>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "capture/daemon/sources.h"
#include "core/check.h"

namespace mocap::capture {

void SimulatedCameraOptions::check() const {
  if (stream.empty()) throw InputError("SimulatedCameraOptions.stream", "is empty");
  if (model.empty()) throw InputError("SimulatedCameraOptions.model", "is empty");
  if (width < 1 || height < 1) throw InputError("SimulatedCameraOptions.width/height", "must be positive");
  if (depth_width < 0 || depth_height < 0 || (depth_width == 0) != (depth_height == 0))
    throw InputError("SimulatedCameraOptions.depth_width/height", "must both be positive, or both 0 (the colour's size)");
  if (jpeg_quality < 1 || jpeg_quality > 100) throw InputError("SimulatedCameraOptions.jpeg_quality", "must be in 1..100");
  if (!(ticks_per_second > 0)) throw InputError("SimulatedCameraOptions.ticks_per_second", "must be positive");
  if (rate_hz < 0) throw InputError("SimulatedCameraOptions.rate_hz", "must be >= 0 (0: unthrottled)");
  if (max_frames < 0) throw InputError("SimulatedCameraOptions.max_frames", "must be >= 0");
}

SimulatedCameraOptions SimulatedKinect1(const std::string& stream) {
  return {.stream = stream, .model = "kinect1", .width = 640, .height = 480, .ticks_per_second = 60e6, .rate_hz = 30};
}

SimulatedCameraOptions SimulatedKinect2(const std::string& stream) {
  return {.stream = stream, .model = "kinect2", .width = 1920, .height = 1080, .depth_width = 512, .depth_height = 424,
          .color_jpeg = true, .ticks_per_second = 8000, .rate_hz = 30};
}

void SimulatedTrackerOptions::check() const {
  if (stream.empty()) throw InputError("SimulatedTrackerOptions.stream", "is empty");
  if (bodies < 1) throw InputError("SimulatedTrackerOptions.bodies", "must be >= 1");
  if (rate_hz < 0) throw InputError("SimulatedTrackerOptions.rate_hz", "must be >= 0 (0: unthrottled)");
  if (max_frames < 0) throw InputError("SimulatedTrackerOptions.max_frames", "must be >= 0");
}

namespace {

// The thread and pacing both simulated sources share: Produce(i) once per period (or as fast as the
// sink is ready when unthrottled) until stopped or `max_items` are produced.
class PacedSource : public CaptureSource {
 public:
  PacedSource(std::string name, double rate_hz, int64_t max_items, ReadyFn ready)
      : CaptureSource(std::move(name)), rate_hz_(rate_hz), max_items_(max_items), ready_(std::move(ready)) {}

  nlohmann::json device_status() const override {
    return {{"kind", "simulated"}, {"rate_hz", rate_hz_}, {"produced", produced_.load()}};
  }

 protected:
  virtual void Produce(int64_t index, int64_t stamp_ns, CaptureSink* sink) = 0;
  void StopThread() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }

 private:
  void DoOpen() override {}
  void DoClose() override {}
  void DoStart(CaptureSink* sink) override {
    stop_ = false;
    thread_ = std::thread([this, sink] { Run(sink); });
  }
  void DoStop() override { StopThread(); }

  void Run(CaptureSink* sink) {
    const int64_t start_ns = MonotonicNowNs();
    const int64_t first = produced_;
    for (int64_t i = first; !stop_ && (max_items_ == 0 || i < max_items_); ++i) {
      if (rate_hz_ > 0) {
        const int64_t due_ns = start_ns + static_cast<int64_t>(static_cast<double>(i - first) * 1e9 / rate_hz_);
        const int64_t wait_ns = due_ns - MonotonicNowNs();
        if (wait_ns > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait_ns));
      } else if (ready_) {
        while (!stop_ && !ready_()) std::this_thread::sleep_for(std::chrono::microseconds(200));
        if (stop_) break;
      }
      Produce(i, MonotonicNowNs(), sink);
      ++produced_;
    }
  }

  double rate_hz_;
  int64_t max_items_;
  ReadyFn ready_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<int64_t> produced_{0};
};

// A test pattern whose content changes from frame to frame (smooth gradients, low noise and a moving
// bar, so PNG encoding costs roughly what camera images cost) and a depth ramp in millimetres. A ring of
// patterns is drawn (and, for JPEG colour, encoded) once; each frame is a copy, as a driver copies its
// USB buffers, except JPEG bytes, which are shared: nothing writes into them.
class SimulatedCamera final : public PacedSource {
 public:
  static constexpr int kPatterns = 8;

  SimulatedCamera(const SimulatedCameraOptions& o, ReadyFn ready)
      : PacedSource(o.stream, o.rate_hz, o.max_frames, std::move(ready)), options_(o) {
    options_.check();
    if (options_.depth_width == 0) {
      options_.depth_width = options_.width;
      options_.depth_height = options_.height;
    }
    for (int k = 0; k < kPatterns; ++k) DrawPattern(k);
  }
  ~SimulatedCamera() override { Close(); }

  StreamInfo stream_info() const override {
    CameraStreamInfo info;
    info.name = name();
    info.model = options_.model;
    info.color_camera = NominalCamera(options_.width, options_.height, 525.0 / 640.0);
    info.depth_registered_to_color = options_.depth_width == options_.width && options_.depth_height == options_.height;
    // An unregistered depth camera (a Kinect v2's ToF sensor) sees wider: 365 px focal length at 512 px.
    info.depth_camera = info.depth_registered_to_color
                            ? info.color_camera
                            : NominalCamera(options_.depth_width, options_.depth_height, 365.0 / 512.0);
    info.depth_unit_m = 0.001;
    return info;
  }

 private:
  static PinholeCamera NominalCamera(int width, int height, double focal_per_px) {
    const double f = focal_per_px * width;
    return {width, height, f, f, (width - 1) / 2.0, (height - 1) / 2.0, {}};
  }

  void DrawPattern(int k) {
    cv::Mat color(options_.height, options_.width, CV_8UC3);
    cv::RNG rng(static_cast<uint64_t>(k) + 1);  // the same ring in every run
    rng.fill(color, cv::RNG::UNIFORM, 0, 24);
    const int bar = k * options_.width / kPatterns;
    for (int v = 0; v < options_.height; ++v) {
      auto* bgr = color.ptr<cv::Vec3b>(v);
      for (int u = 0; u < options_.width; ++u)
        bgr[u] += cv::Vec3b(static_cast<uint8_t>(u / 3), static_cast<uint8_t>(v / 2), std::abs(u - bar) < 20 ? 200 : 0);
    }
    cv::Mat depth(options_.depth_height, options_.depth_width, CV_16UC1);
    const int depth_bar = k * options_.depth_width / kPatterns;
    for (int v = 0; v < options_.depth_height; ++v) {
      auto* mm = depth.ptr<uint16_t>(v);
      for (int u = 0; u < options_.depth_width; ++u) mm[u] = static_cast<uint16_t>(std::abs(u - depth_bar) < 8 ? 800 : 1500 + v);
    }
    if (options_.color_jpeg) {
      auto jpeg = std::make_shared<std::vector<uint8_t>>();
      MOCAP_CHECK(cv::imencode(".jpg", color, *jpeg, {cv::IMWRITE_JPEG_QUALITY, options_.jpeg_quality}), "JPEG encoding failed");
      jpegs_.push_back(std::move(jpeg));
    } else {
      colors_.push_back(color);
    }
    depths_.push_back(depth);
  }

  void Produce(int64_t index, int64_t stamp_ns, CaptureSink* sink) override {
    const auto k = static_cast<size_t>(index % kPatterns);
    const double rate_hz = options_.rate_hz > 0 ? options_.rate_hz : 30.0;
    CapturedFrame frame;
    frame.camera = name();
    frame.record.frame = index;
    frame.record.device_ticks = std::llround(static_cast<double>(index) * options_.ticks_per_second / rate_hz);
    frame.record.stamp_ns = stamp_ns;
    if (options_.color_jpeg) frame.color_jpeg = jpegs_[k];
    else frame.color = colors_[k].clone();
    frame.depth = depths_[k].clone();
    sink->PushFrame(std::move(frame));
  }

  SimulatedCameraOptions options_;
  std::vector<cv::Mat> colors_, depths_;
  std::vector<std::shared_ptr<const std::vector<uint8_t>>> jpegs_;
};

class SimulatedTracker final : public PacedSource {
 public:
  SimulatedTracker(const SimulatedTrackerOptions& o, ReadyFn ready)
      : PacedSource(o.stream, o.rate_hz, o.max_frames, std::move(ready)), options_(o) {
    options_.check();
  }
  ~SimulatedTracker() override { Close(); }

  StreamInfo stream_info() const override {
    TrackerStreamInfo info;
    info.name = name();
    info.model = "sim";
    for (int b = 0; b < options_.bodies; ++b) info.bodies.push_back(Str("body", b));
    return info;
  }

 private:
  void Produce(int64_t index, int64_t stamp_ns, CaptureSink* sink) override {
    const double t_s = static_cast<double>(index) / (options_.rate_hz > 0 ? options_.rate_hz : 400.0);
    for (int b = 0; b < options_.bodies; ++b) {
      const double angle = t_s * (1.0 + b) * 0.5;
      CapturedSample sample;
      sample.tracker = name();
      sample.record.body = Str("body", b);
      sample.record.device_frame = index;
      sample.record.stamp_ns = stamp_ns;
      sample.record.T_frame_body = Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ())),
                                           Eigen::Vector3d(0.1 * std::cos(angle), 0.1 * std::sin(angle), -1.5));
      sample.record.rms_error_m = 1e-4;
      sink->PushSample(std::move(sample));
    }
  }

  SimulatedTrackerOptions options_;
};

}  // namespace

std::unique_ptr<CaptureSource> CreateSimulatedCamera(const SimulatedCameraOptions& options, ReadyFn ready) {
  return std::make_unique<SimulatedCamera>(options, std::move(ready));
}

std::unique_ptr<CaptureSource> CreateSimulatedTracker(const SimulatedTrackerOptions& options, ReadyFn ready) {
  return std::make_unique<SimulatedTracker>(options, std::move(ready));
}

}  // namespace mocap::capture
