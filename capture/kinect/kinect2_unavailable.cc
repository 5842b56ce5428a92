// Kinect2 entry points for builds without libfreenect2 (the usual case on Debian).
#include "core/check.h"
#include "capture/kinect/kinect2_support.h"

namespace mocap::capture {

bool Kinect2SupportBuilt() { return false; }

std::string Kinect2SupportDetail() {
  return "not built: libfreenect2 was not found when mocaplabel was configured (Debian does not package it; "
         "build it from source and reconfigure, see docs/kinect.md)";
}

std::unique_ptr<CameraDevice> CreateKinect2Device(const Kinect2Options& options) {
  options.check();
  throw DeviceError("kinect2: support " + Kinect2SupportDetail());
}

}  // namespace mocap::capture
