// Kinect2 through libfreenect2 (compiled only when CMake found libfreenect2). Colour 1920x1080 BGRX (or
// the device's JPEG, where the pipeline hands it over undecoded) and depth 512x424 float mm arrive
// together from a SyncMultiFrameListener; depth is mapped into the colour
// image by libfreenect2's Registration ("bigdepth", 1920x1082 with a blank first and last row) when
// registered_depth is on. The frame timestamp counts 0.125 ms (8000 ticks/s), converted to ns at the edge.
#include <libfreenect2/frame_listener_impl.h>
#include <libfreenect2/libfreenect2.hpp>
#include <libfreenect2/packet_pipeline.h>
#include <libfreenect2/registration.h>

#include <atomic>
#include <cmath>
#include <thread>

#include <opencv2/imgproc.hpp>

#include "capture/kinect/kinect2_support.h"
#include "core/check.h"
#include "core/clock.h"

namespace mocap::capture {
namespace {

constexpr double kKinect2TicksPerSecond = 8000.0;  // 0.125 ms

libfreenect2::PacketPipeline* MakePipeline(const std::string& name) {
  if (name.empty()) return nullptr;  // libfreenect2's default
  if (name == "cpu") return new libfreenect2::CpuPacketPipeline();
#ifdef LIBFREENECT2_WITH_OPENGL_SUPPORT
  if (name == "opengl") return new libfreenect2::OpenGLPacketPipeline();
#endif
#ifdef LIBFREENECT2_WITH_OPENCL_SUPPORT
  if (name == "opencl") return new libfreenect2::OpenCLPacketPipeline();
#endif
#ifdef LIBFREENECT2_WITH_CUDA_SUPPORT
  if (name == "cuda") return new libfreenect2::CudaPacketPipeline();
#endif
  throw DeviceError("kinect2: this libfreenect2 was built without the '" + name + "' pipeline");
}

// Float mm (non-positive, NaN, inf = no value) to CV_16UC1 mm with 0 = no value.
cv::Mat DepthToMm(const float* depth, int width, int height) {
  cv::Mat depth_mm(height, width, CV_16UC1);
  auto* out = depth_mm.ptr<uint16_t>();
  for (int i = 0; i < width * height; ++i) {
    const float mm = depth[i];
    out[i] = (std::isfinite(mm) && mm > 0.0f && mm < 65535.0f) ? static_cast<uint16_t>(std::lround(mm)) : 0;
  }
  return depth_mm;
}

class Kinect2Device final : public CameraDevice {
 public:
  explicit Kinect2Device(const Kinect2Options& options)
      : CameraDevice("kinect2"), options_(options),
        listener_(libfreenect2::Frame::Color | libfreenect2::Frame::Depth) {}
  ~Kinect2Device() override { Close(); }

 private:
  void DoOpen() override {
    if (context_.enumerateDevices() <= 0)
      throw DeviceError("kinect2: no Kinect2 attached (libfreenect2 found no 045e:02d8 / 045e:02c4 on USB 3)");
    const std::string serial = options_.serial.empty() ? context_.getDefaultDeviceSerialNumber() : options_.serial;
    libfreenect2::PacketPipeline* pipeline = MakePipeline(options_.pipeline);
    device_ = pipeline ? context_.openDevice(serial, pipeline) : context_.openDevice(serial);
    if (!device_)
      throw DeviceError("kinect2: cannot open " + serial +
                        " (busy, no permission: install libfreenect2's 90-kinect2.rules, or not on USB 3)");
    libfreenect2::Freenect2Device::Config config;
    config.MinDepth = static_cast<float>(options_.min_depth_m);
    config.MaxDepth = static_cast<float>(options_.max_depth_m);
    config.EnableBilateralFilter = options_.bilateral_filter;
    config.EnableEdgeAwareFilter = options_.edge_aware_filter;
    device_->setConfiguration(config);
    device_->setColorFrameListener(&listener_);
    device_->setIrAndDepthFrameListener(&listener_);
  }

  void DoStart() override {
    if (!device_->start()) throw DeviceError("kinect2: cannot start the streams");
    // Factory parameters are read from the device when it starts.
    const auto color = device_->getColorCameraParams();
    const auto ir = device_->getIrCameraParams();
    registration_ = std::make_unique<libfreenect2::Registration>(ir, color);
    color_camera_ = PinholeCamera{1920, 1080, color.fx, color.fy, color.cx, color.cy, {}};
    ir_camera_ = PinholeCamera{512, 424, ir.fx, ir.fy, ir.cx, ir.cy, {ir.k1, ir.k2, ir.p1, ir.p2, ir.k3, 0, 0, 0}};
    depth_unwrapper_ = CounterUnwrapper(32);
    color_unwrapper_ = CounterUnwrapper(32);
    stop_ = false;
    thread_ = std::thread([this] { Run(); });
  }

  void Run() {
    libfreenect2::FrameMap frames;
    while (!stop_) {
      if (!listener_.waitForNewFrame(frames, options_.frame_timeout_ms)) {
        if (!stop_) ReportStreamEnd(Str("kinect2: no frame within ", options_.frame_timeout_ms, " ms (unplugged?)"));
        return;
      }
      try {
        Emit(frames[libfreenect2::Frame::Color], frames[libfreenect2::Frame::Depth]);
      } catch (const std::exception& e) {
        listener_.release(frames);
        ReportStreamEnd(std::string("kinect2: the frame callback failed: ") + e.what());
        return;
      }
      listener_.release(frames);
    }
  }

  void Emit(const libfreenect2::Frame* color, const libfreenect2::Frame* depth) {
    RgbdFrame frame;
    frame.color_host_ns = frame.depth_host_ns = MonotonicNowNs();
    if (color->format == libfreenect2::Frame::Raw) {
      // Undecoded colour (DumpRgbPacketProcessor): the device's JPEG, its length in bytes_per_pixel
      // (libfreenect2 rgb_packet_processor.cpp), cut at its end-of-image marker by the stream parser.
      frame.color_jpeg = std::make_shared<const std::vector<uint8_t>>(color->data, color->data + color->bytes_per_pixel);
    } else {
      const cv::Mat colorx(static_cast<int>(color->height), static_cast<int>(color->width), CV_8UC4, color->data);
      cv::cvtColor(colorx, frame.bgr, color->format == libfreenect2::Frame::RGBX ? cv::COLOR_RGBA2BGR : cv::COLOR_BGRA2BGR);
    }
    // Registration reads the decoded colour frame (Registration::apply returns at once for a Raw one):
    // with JPEG colour the depth stays in the 512x424 IR camera.
    if (options_.registered_depth && !frame.color_jpeg) {
      libfreenect2::Frame undistorted(512, 424, 4), registered(512, 424, 4), bigdepth(1920, 1082, 4);
      registration_->apply(color, depth, &undistorted, &registered, true, &bigdepth);
      // Row 0 and row 1081 of bigdepth are padding; rows 1..1080 line up with the colour image.
      frame.depth_mm = DepthToMm(reinterpret_cast<const float*>(bigdepth.data) + 1920, 1920, 1080);
      frame.depth_camera = color_camera_;
      frame.depth_registered = true;
    } else {
      frame.depth_mm = DepthToMm(reinterpret_cast<const float*>(depth->data), 512, 424);
      frame.depth_camera = ir_camera_;
    }
    frame.intrinsics_source = "device";
    frame.depth_ticks_raw = depth->timestamp;
    frame.color_ticks_raw = color->timestamp;
    frame.depth_ticks = depth_unwrapper_.Unwrap(depth->timestamp);
    frame.color_ticks = color_unwrapper_.Unwrap(color->timestamp);
    frame.ticks_per_second = kKinect2TicksPerSecond;
    SetStreamCounts(0, 0, depth_unwrapper_.wraps());
    Deliver(std::move(frame));
  }

  void DoStop() override {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    device_->stop();
  }

  void DoClose() override {
    if (device_) device_->close();
    delete device_;  // libfreenect2 hands devices out as owning raw pointers
    device_ = nullptr;
  }

  Kinect2Options options_;
  libfreenect2::Freenect2 context_;
  libfreenect2::Freenect2Device* device_ = nullptr;
  libfreenect2::SyncMultiFrameListener listener_;
  std::unique_ptr<libfreenect2::Registration> registration_;
  PinholeCamera color_camera_, ir_camera_;
  CounterUnwrapper depth_unwrapper_{32};
  CounterUnwrapper color_unwrapper_{32};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace

bool Kinect2SupportBuilt() { return true; }

std::string Kinect2SupportDetail() { return std::string("built with libfreenect2 ") + LIBFREENECT2_VERSION; }

std::unique_ptr<CameraDevice> CreateKinect2Device(const Kinect2Options& options) {
  options.check();
  return std::make_unique<Kinect2Device>(options);
}

}  // namespace mocap::capture
