#pragma once
// Kinect1 (Xbox 360 Kinect 045e:02ae, Kinect for Windows 045e:02bf) through libfreenect 0.5.3: colour
// FREENECT_VIDEO_RGB 640x480 @ 30 Hz and depth 640x480 @ 30 Hz, delivered as RgbdFrame pairs.
//
// Depth: FREENECT_DEPTH_REGISTERED (mm, aligned to colour, computed by libfreenect from the tables the
// device sends at open) when the loaded libfreenect exports its registration API; otherwise
// FREENECT_DEPTH_11BIT converted to mm with the device's raw-to-mm table, or, without one (fakenect
// replay), with the fit in kinect1_depth.h. Optional libfreenect calls are looked up with dlsym so the
// same binary runs against fakenect, which lacks them (kinect.md §5).
// Timestamps: the 32-bit 60 MHz counter of each stream, unwrapped (wrap every 71.58 s); host
// CLOCK_MONOTONIC taken in the callback. Accelerometer/tilt from the motor subdevice when present.
#include <memory>
#include <optional>
#include <string>

#include "core/camera.h"
#include "capture/kinect/camera_device.h"

namespace mocap::capture {

inline constexpr double kKinect1TicksPerSecond = 60e6;

struct Kinect1Options {
  int device_index = 0;       ///< libfreenect device index, used when camera_serial is empty
  std::string camera_serial;  ///< open the Kinect with this camera serial instead
  /// Ask for depth registered to colour when the library can (real hardware). Off: unregistered depth.
  bool registered_depth = true;
  bool read_tilt = true;                  ///< open the motor subdevice and read the accelerometer
  double tilt_poll_interval_ms = 30.0;    ///< at most one accelerometer read per interval (a USB transfer)
  double pair_tolerance_ms = 10.0;        ///< colour and depth with device times further apart are not paired
  /// Intrinsics of the depth image, overriding what the device or recording provides (a calibration).
  std::optional<PinholeCamera> depth_camera;
  /// Throws InputError on a negative index or interval, or a non-positive tolerance.
  void check() const;
};

/// What the libfreenect loaded into this process offers.
struct LibfreenectInfo {
  bool registration = false;  ///< exports freenect_copy_registration (the real library does)
  bool replay = false;        ///< the fakenect build (no registration API); replays FAKENECT_PATH
  std::string fakenect_path;  ///< $FAKENECT_PATH, when set
};
LibfreenectInfo ProbeLibfreenect();

/// "libfreenect <version> (...)": the library this build links, for `mocaplabel devices`.
std::string Kinect1SupportDetail();

/// The nominal depth-camera intrinsics of libfreenect's examples/glpclview.c (N. Burrus): fx 594.21,
/// fy 591.04, cx 339.5, cy 242.7, no distortion; used when nothing better is known.
PinholeCamera NominalKinect1DepthCamera();

/// A Kinect1 in state Created; Open() finds and opens it (throws DeviceError when none is attached).
std::unique_ptr<CameraDevice> CreateKinect1Device(const Kinect1Options& options = {});

}  // namespace mocap::capture
