#pragma once
// The pinhole model's last step, from normalised image coordinates to pixels, inline: PinholeCamera's
// Project (camera.cc) ends with it, and per-point loops that would call Project for a camera without
// distortion (the validator's frame visibility, once per crop point) use it in place of the call, so
// both compute the same pixel the same way.
#include <Eigen/Core>

#include "core/camera.h"

namespace mocap {

/// Pixel of normalised (distorted) image coordinates (x, y): (fx x + cx, fy y + cy).
inline Eigen::Vector2d PixelOfNormalised(const PinholeCamera& camera, double x, double y) {
  return {camera.fx * x + camera.cx, camera.fy * y + camera.cy};
}

/// PinholeCamera::Project for a camera without distortion and a point in front of it (z > 0).
inline Eigen::Vector2d ProjectWithoutDistortion(const PinholeCamera& camera, const Eigen::Vector3d& point_camera) {
  return PixelOfNormalised(camera, point_camera.x() / point_camera.z(), point_camera.y() / point_camera.z());
}

}  // namespace mocap
