#pragma once
// Kinect2 (045e:02d8, preview 045e:02c4) goes through libfreenect2, which Debian does not package. The
// build looks for it at configure time and compiles the Kinect2 device only when found; these say which.
#include <memory>
#include <string>

#include "capture/kinect/camera_device.h"

namespace mocap::capture {

/// True when this build links libfreenect2 and CreateKinect2Device can open a Kinect2.
bool Kinect2SupportBuilt();
/// One line for users: the libfreenect2 version built against, or why Kinect2 support is missing and how
/// to get it.
std::string Kinect2SupportDetail();

struct Kinect2Options {
  std::string serial;              ///< empty: the first Kinect2
  /// libfreenect2 packet pipeline: "cpu", "opengl", "opencl", "cuda" (empty: libfreenect2's default).
  std::string pipeline;
  double min_depth_m = 0.5;        ///< libfreenect2 Config::MinDepth
  double max_depth_m = 4.5;        ///< libfreenect2 Config::MaxDepth
  bool bilateral_filter = true;    ///< Config::EnableBilateralFilter ("remove some flying pixels")
  bool edge_aware_filter = true;   ///< Config::EnableEdgeAwareFilter
  int frame_timeout_ms = 1000;     ///< waiting longer than this for a frame ends the stream
  /// Map depth into the 1920x1080 colour image (libfreenect2 Registration); off: 512x424 IR-camera depth.
  bool registered_depth = true;
  /// Throws InputError on a bad range, an unknown pipeline or a non-positive timeout.
  void check() const;
};

/// A Kinect2 in state Created. Throws DeviceError when Kinect2 support was not built (with the reason).
std::unique_ptr<CameraDevice> CreateKinect2Device(const Kinect2Options& options = {});

}  // namespace mocap::capture
