#pragma once
// The camera of the render tests: a Kinect v1-like 640x480 pinhole, optionally with strong radial
// distortion (k1..k3 of a real Kinect v1 calibration) to test the renderer's distortion path.
#include "core/camera.h"

namespace mocap::test {

inline PinholeCamera TestCamera(bool distorted) {
  PinholeCamera cam{640, 480, 525.0, 525.0, 319.5, 239.5, {}};
  if (distorted) cam.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633, 0, 0, 0};
  return cam;
}

}  // namespace mocap::test
