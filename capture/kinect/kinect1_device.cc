#include "capture/kinect/kinect1_device.h"

#include <dlfcn.h>
#include <libfreenect.h>
#include <libfreenect_registration.h>
#include <sys/time.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <thread>

#include <opencv2/imgproc.hpp>

#include "core/check.h"
#include "core/clock.h"
#include "capture/kinect/fakenect_recording.h"
#include "capture/kinect/frame_pairer.h"
#include "capture/kinect/kinect1_depth.h"

namespace mocap::capture {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;
// libusb's LIBUSB_ERROR_INTERRUPTED: a signal arrived during the wait, not a device failure.
constexpr int kUsbInterrupted = -10;

using CopyRegistrationFn = freenect_registration (*)(freenect_device*);
using DestroyRegistrationFn = int (*)(freenect_registration*);

template <typename Fn>
Fn LookUp(const char* symbol) {
  return reinterpret_cast<Fn>(dlsym(RTLD_DEFAULT, symbol));
}

// Optional device calibration, read once at open while the device is not streaming.
struct DeviceCalibration {
  std::optional<Raw11ToMmTable> raw_to_mm;
  std::optional<PinholeCamera> zero_plane_camera;
};

DeviceCalibration ReadDeviceCalibration(freenect_device* device) {
  auto copy = LookUp<CopyRegistrationFn>("freenect_copy_registration");
  auto destroy = LookUp<DestroyRegistrationFn>("freenect_destroy_registration");
  DeviceCalibration calibration;
  if (!copy || !destroy) return calibration;
  freenect_registration registration = copy(device);
  if (registration.raw_to_mm_shift)
    calibration.raw_to_mm = Raw11ToMmTable::FromDevice({registration.raw_to_mm_shift, 2048});
  const freenect_zero_plane_info& zero_plane = registration.zero_plane_info;
  if (zero_plane.reference_distance > 0 && zero_plane.reference_pixel_size > 0) {
    // freenect_camera_to_world: x = (u - 320) * 2 * pixel_size * z / reference_distance, so
    // f = reference_distance / (2 * pixel_size) at 640x480, principal point at the image centre.
    const double f = zero_plane.reference_distance / (2.0 * zero_plane.reference_pixel_size);
    calibration.zero_plane_camera = PinholeCamera{kWidth, kHeight, f, f, 320.0, 240.0, {}};
  }
  destroy(&registration);
  return calibration;
}

class Kinect1Device final : public CameraDevice {
 public:
  explicit Kinect1Device(const Kinect1Options& options)
      : CameraDevice("kinect1"), options_(options),
        pairer_(std::llround(options.pair_tolerance_ms * 1e-3 * kKinect1TicksPerSecond)) {}
  ~Kinect1Device() override { Close(); }

 private:
  void DoOpen() override;
  void DoStart() override;
  void DoStop() override;
  void DoClose() override;

  void OpenWith(int subdevices);
  void ChooseModes();
  void Run();
  void PollTilt();
  void OnDepth(const void* data, uint32_t ticks_raw);
  void OnColor(const void* data, uint32_t ticks_raw);
  void Emit(ImagePair&& pair);

  // Exceptions must not unwind through libfreenect's C frames (it would skip its own clean-up): the
  // trampolines keep the first failure and Run() ends the stream with it once the C call has returned.
  static void DepthTrampoline(freenect_device* device, void* data, uint32_t timestamp) {
    auto* self = static_cast<Kinect1Device*>(freenect_get_user(device));
    self->Guarded([&] { self->OnDepth(data, timestamp); });
  }
  static void ColorTrampoline(freenect_device* device, void* data, uint32_t timestamp) {
    auto* self = static_cast<Kinect1Device*>(freenect_get_user(device));
    self->Guarded([&] { self->OnColor(data, timestamp); });
  }
  template <typename Fn>
  void Guarded(Fn&& fn) {
    if (callback_error_) return;
    try {
      fn();
    } catch (const std::exception& e) {
      callback_error_ = std::string("kinect1: the frame callback failed: ") + e.what();
    }
  }
  std::optional<std::string> callback_error_;

  Kinect1Options options_;
  LibfreenectInfo library_;
  freenect_context* context_ = nullptr;
  freenect_device* device_ = nullptr;
  bool tilt_available_ = false;
  bool registered_mode_ = false;
  bool depth_registered_ = false;
  Raw11ToMmTable raw_to_mm_ = Raw11ToMmTable::FromFit();
  PinholeCamera depth_camera_;
  std::string intrinsics_source_;

  std::thread thread_;
  std::atomic<bool> stop_{false};
  FramePairer pairer_;
  CounterUnwrapper depth_unwrapper_{32};
  CounterUnwrapper color_unwrapper_{32};
  std::optional<TiltSample> latest_tilt_;
  int64_t last_tilt_poll_ns_ = 0;
};

void Kinect1Device::DoOpen() {
  library_ = ProbeLibfreenect();
  if (library_.replay) {
    // fakenect calls exit(1) on a missing path or index; say so here instead.
    if (library_.fakenect_path.empty())
      throw DeviceError("kinect1: the fakenect replay build of libfreenect is loaded (LD_LIBRARY_PATH) but "
                        "FAKENECT_PATH is not set; set it to a fakenect recording directory");
    if (!std::filesystem::exists(std::filesystem::path(library_.fakenect_path) / "INDEX.txt"))
      throw DeviceError("kinect1: FAKENECT_PATH=" + library_.fakenect_path + " holds no INDEX.txt (not a fakenect recording)");
  }
  const int motor = options_.read_tilt ? FREENECT_DEVICE_MOTOR : 0;
  try {
    OpenWith(FREENECT_DEVICE_CAMERA | motor);
    tilt_available_ = motor != 0;
  } catch (const DeviceError&) {
    if (motor == 0) throw;
    OpenWith(FREENECT_DEVICE_CAMERA);  // models without a reachable motor subdevice
  }
  try {
    ChooseModes();
  } catch (...) {
    DoClose();
    throw;
  }
}

void Kinect1Device::OpenWith(int subdevices) {
  if (freenect_init(&context_, nullptr) < 0)
    throw DeviceError("kinect1: libfreenect could not initialise libusb (is /dev/bus/usb available?)");
  freenect_set_log_level(context_, FREENECT_LOG_WARNING);
  freenect_select_subdevices(context_, static_cast<freenect_device_flags>(subdevices));
  const int count = freenect_num_devices(context_);
  std::string error;
  if (count <= 0) {
    error = "kinect1: no Kinect1 attached (libfreenect found no 045e:02ae / 045e:02bf camera)";
  } else if (options_.camera_serial.empty() && options_.device_index >= count) {
    error = Str("kinect1: device index ", options_.device_index, " but only ", count, " Kinect1 attached");
  } else {
    const int rc = options_.camera_serial.empty()
                       ? freenect_open_device(context_, &device_, options_.device_index)
                       : freenect_open_device_by_camera_serial(context_, &device_, options_.camera_serial.c_str());
    if (rc < 0)
      error = Str("kinect1: cannot open the device (error ", rc,
                  "; busy in another program, or no permission: install libfreenect's 51-kinect.rules udev rules)");
  }
  if (!error.empty()) {
    freenect_shutdown(context_);
    context_ = nullptr;
    device_ = nullptr;
    throw DeviceError(error);
  }
}

void Kinect1Device::ChooseModes() {
  const DeviceCalibration calibration = ReadDeviceCalibration(device_);
  registered_mode_ = options_.registered_depth && library_.registration;
  const freenect_depth_format depth_format = registered_mode_ ? FREENECT_DEPTH_REGISTERED : FREENECT_DEPTH_11BIT;
  if (freenect_set_depth_mode(device_, freenect_find_depth_mode(FREENECT_RESOLUTION_MEDIUM, depth_format)) < 0 ||
      freenect_set_video_mode(device_, freenect_find_video_mode(FREENECT_RESOLUTION_MEDIUM, FREENECT_VIDEO_RGB)) < 0)
    throw DeviceError("kinect1: the device refused 640x480 RGB + depth at 30 Hz");
  if (calibration.raw_to_mm) raw_to_mm_ = *calibration.raw_to_mm;

  depth_registered_ = registered_mode_;
  depth_camera_ = NominalKinect1DepthCamera();
  intrinsics_source_ = "nominal";
  if (calibration.zero_plane_camera) {
    depth_camera_ = *calibration.zero_plane_camera;
    intrinsics_source_ = "device";
  }
  if (library_.replay) {
    if (auto recorded = ReadRecordingCamera(library_.fakenect_path)) {
      depth_camera_ = recorded->depth_camera;
      depth_registered_ = recorded->depth_registered;
      intrinsics_source_ = "recording";
    }
  }
  if (options_.depth_camera) {
    depth_camera_ = *options_.depth_camera;
    intrinsics_source_ = "options";
  }
  freenect_set_user(device_, this);
  freenect_set_depth_callback(device_, &DepthTrampoline);
  freenect_set_video_callback(device_, &ColorTrampoline);
}

void Kinect1Device::DoStart() {
  pairer_ = FramePairer(std::llround(options_.pair_tolerance_ms * 1e-3 * kKinect1TicksPerSecond));
  depth_unwrapper_ = CounterUnwrapper(32);
  color_unwrapper_ = CounterUnwrapper(32);
  if (freenect_start_depth(device_) < 0 || freenect_start_video(device_) < 0) {
    freenect_stop_depth(device_);
    throw DeviceError("kinect1: cannot start the depth and colour streams");
  }
  stop_ = false;
  callback_error_.reset();
  thread_ = std::thread([this] { Run(); });
}

void Kinect1Device::Run() {
  while (!stop_) {
    timeval timeout{0, 100'000};
    const int rc = freenect_process_events_timeout(context_, &timeout);  // runs the frame callbacks
    if (callback_error_) {
      ReportStreamEnd(*callback_error_);
      return;
    }
    if (rc < 0 && rc != kUsbInterrupted) {
      ReportStreamEnd(library_.replay ? "end of the fakenect recording " + library_.fakenect_path
                                      : Str("libfreenect stopped with error ", rc, " (device unplugged?)"));
      return;
    }
    PollTilt();
  }
}

void Kinect1Device::PollTilt() {
  if (!tilt_available_) return;
  const int64_t now_ns = MonotonicNowNs();
  if (now_ns - last_tilt_poll_ns_ < std::llround(options_.tilt_poll_interval_ms * 1e6)) return;
  last_tilt_poll_ns_ = now_ns;
  if (freenect_update_tilt_state(device_) < 0) return;
  freenect_raw_tilt_state* state = freenect_get_tilt_state(device_);
  // A real accelerometer always feels gravity; all-zero counts mean no reading has arrived yet.
  if (!state || (state->accelerometer_x == 0 && state->accelerometer_y == 0 && state->accelerometer_z == 0)) return;
  TiltSample tilt;
  tilt.accel_raw[0] = state->accelerometer_x;
  tilt.accel_raw[1] = state->accelerometer_y;
  tilt.accel_raw[2] = state->accelerometer_z;
  freenect_get_mks_accel(state, &tilt.accel_mps2[0], &tilt.accel_mps2[1], &tilt.accel_mps2[2]);
  tilt.tilt_deg = freenect_get_tilt_degs(state);
  tilt.tilt_status = static_cast<int>(freenect_get_tilt_status(state));
  tilt.host_ns = now_ns;
  latest_tilt_ = tilt;
}

void Kinect1Device::OnDepth(const void* data, uint32_t ticks_raw) {
  StampedImage depth;
  depth.host_ns = MonotonicNowNs();
  depth.ticks_raw = ticks_raw;
  depth.ticks = depth_unwrapper_.Unwrap(ticks_raw);
  if (registered_mode_) {
    depth.image.create(kHeight, kWidth, CV_16UC1);
    std::memcpy(depth.image.data, data, depth.image.total() * sizeof(uint16_t));  // data may be unaligned
  } else {
    depth.image = raw_to_mm_.Convert(data, kWidth, kHeight);
  }
  if (auto pair = pairer_.AddDepth(std::move(depth))) Emit(std::move(*pair));
}

void Kinect1Device::OnColor(const void* data, uint32_t ticks_raw) {
  StampedImage color;
  color.host_ns = MonotonicNowNs();
  color.ticks_raw = ticks_raw;
  color.ticks = color_unwrapper_.Unwrap(ticks_raw);
  const cv::Mat rgb(kHeight, kWidth, CV_8UC3, const_cast<void*>(data));
  cv::cvtColor(rgb, color.image, cv::COLOR_RGB2BGR);
  if (auto pair = pairer_.AddColor(std::move(color))) Emit(std::move(*pair));
}

void Kinect1Device::Emit(ImagePair&& pair) {
  SetStreamCounts(pairer_.depth_unpaired(), pairer_.color_unpaired(), depth_unwrapper_.wraps());
  RgbdFrame frame;
  frame.bgr = std::move(pair.color.image);
  frame.depth_mm = std::move(pair.depth.image);
  frame.depth_registered = depth_registered_;
  frame.depth_camera = depth_camera_;
  frame.intrinsics_source = intrinsics_source_;
  frame.depth_ticks_raw = pair.depth.ticks_raw;
  frame.color_ticks_raw = pair.color.ticks_raw;
  frame.depth_ticks = pair.depth.ticks;
  frame.color_ticks = pair.color.ticks;
  frame.ticks_per_second = kKinect1TicksPerSecond;
  frame.depth_host_ns = pair.depth.host_ns;
  frame.color_host_ns = pair.color.host_ns;
  frame.tilt = latest_tilt_;
  Deliver(std::move(frame));
}

void Kinect1Device::DoStop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  freenect_stop_depth(device_);
  freenect_stop_video(device_);
}

void Kinect1Device::DoClose() {
  if (device_) freenect_close_device(device_);
  if (context_) freenect_shutdown(context_);
  device_ = nullptr;
  context_ = nullptr;
}

}  // namespace

void Kinect1Options::check() const {
  if (device_index < 0) throw InputError("Kinect1Options", "device_index must be >= 0");
  if (!(tilt_poll_interval_ms >= 0)) throw InputError("Kinect1Options", "tilt_poll_interval_ms must be >= 0");
  if (!(pair_tolerance_ms > 0)) throw InputError("Kinect1Options", "pair_tolerance_ms must be positive");
  if (depth_camera) depth_camera->check();
}

LibfreenectInfo ProbeLibfreenect() {
  LibfreenectInfo info;
  info.registration = dlsym(RTLD_DEFAULT, "freenect_copy_registration") != nullptr;
  info.replay = !info.registration;
  if (const char* path = std::getenv("FAKENECT_PATH")) info.fakenect_path = path;
  return info;
}

std::string Kinect1SupportDetail() {
  const LibfreenectInfo info = ProbeLibfreenect();
  return Str("built with libfreenect ", MOCAP_LIBFREENECT_VERSION,
             info.replay ? "; the fakenect replay build is loaded (FAKENECT_PATH=" + info.fakenect_path + ")" : "");
}

PinholeCamera NominalKinect1DepthCamera() { return PinholeCamera{640, 480, 594.21, 591.04, 339.5, 242.7, {}}; }

std::unique_ptr<CameraDevice> CreateKinect1Device(const Kinect1Options& options) {
  options.check();
  return std::make_unique<Kinect1Device>(options);
}

}  // namespace mocap::capture
