#include "core/camera.h"

#include <Eigen/LU>

#include "core/check.h"
#include "core/pinhole.h"

namespace mocap {

void PinholeCamera::check() const {
  if (width <= 0 || height <= 0) throw InputError("camera", Str("image size ", width, "x", height, " is not positive"));
  if (!(fx > 0) || !(fy > 0)) throw InputError("camera", Str("focal lengths fx=", fx, " fy=", fy, " must be positive"));
}

bool PinholeCamera::has_distortion() const {
  for (double d : dist)
    if (d != 0.0) return true;
  return false;
}

Eigen::Matrix3d PinholeCamera::K() const {
  Eigen::Matrix3d k;
  k << fx, 0, cx, 0, fy, cy, 0, 0, 1;
  return k;
}

Eigen::Vector2d PinholeCamera::Distort(const Eigen::Vector2d& xy) const {
  if (!has_distortion()) return xy;  // the model below is then the identity (radial term 1, tangential 0)
  // OpenCV's model (calib3d "Detailed description"): radial rational term and tangential p1, p2.
  const auto& [k1, k2, p1, p2, k3, k4, k5, k6] = dist;
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
  const double radial = (1 + k1 * r2 + k2 * r4 + k3 * r6) / (1 + k4 * r2 + k5 * r4 + k6 * r6);
  return {x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x), y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y};
}

Eigen::Vector2d PinholeCamera::Undistort(const Eigen::Vector2d& xy_distorted) const {
  if (!has_distortion()) return xy_distorted;
  // Newton's method on Distort(xy) = xy_distorted with a central-difference Jacobian: the fixed-point
  // iteration of cv::undistortPoints stalls near the corners of strongly distorted lenses.
  Eigen::Vector2d xy = xy_distorted;
  constexpr double h = 1e-7;
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector2d residual = Distort(xy) - xy_distorted;
    if (residual.norm() < 1e-15) break;
    Eigen::Matrix2d J;
    J.col(0) = (Distort(xy + Eigen::Vector2d(h, 0)) - Distort(xy - Eigen::Vector2d(h, 0))) / (2 * h);
    J.col(1) = (Distort(xy + Eigen::Vector2d(0, h)) - Distort(xy - Eigen::Vector2d(0, h))) / (2 * h);
    xy -= J.partialPivLu().solve(residual);
  }
  return xy;
}

std::optional<Eigen::Vector2d> PinholeCamera::Project(const Eigen::Vector3d& point_camera) const {
  if (point_camera.z() <= 0) return std::nullopt;
  const Eigen::Vector2d d = Distort(point_camera.head<2>() / point_camera.z());
  return PixelOfNormalised(*this, d.x(), d.y());
}

Eigen::Vector3d PinholeCamera::Ray(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d xy = Undistort({(pixel.x() - cx) / fx, (pixel.y() - cy) / fy});
  return {xy.x(), xy.y(), 1.0};
}

Eigen::Vector3d PinholeCamera::Unproject(const Eigen::Vector2d& pixel, double z_m) const { return Ray(pixel) * z_m; }

namespace {

/// Back-projection of an image's pixels. Without distortion a pixel's ray is ((u - cx) / fx, (v - cy) / fy,
/// 1), Ray's own arithmetic, worked out once per column and per row rather than per pixel (the validator
/// back-projects every record's mask); with distortion each pixel goes through Unproject.
class PixelRays {
 public:
  /// For the pixels of an image `width` x `height`.
  PixelRays(const PinholeCamera& camera, int width, int height) : camera_(camera), pinhole_(!camera.has_distortion()) {
    if (!pinhole_) return;
    for (int u = 0; u < width; ++u) x_of_u_.push_back((static_cast<double>(u) - camera.cx) / camera.fx);
    for (int v = 0; v < height; ++v) y_of_v_.push_back((static_cast<double>(v) - camera.cy) / camera.fy);
  }
  /// Unproject({u, v}, z_m); (u, v) inside that image.
  Eigen::Vector3d Point(int u, int v, float z_m) const {
    if (!pinhole_) return camera_.Unproject({u, v}, z_m);
    return Eigen::Vector3d(x_of_u_[static_cast<size_t>(u)], y_of_v_[static_cast<size_t>(v)], 1.0) * static_cast<double>(z_m);
  }

 private:
  const PinholeCamera& camera_;
  bool pinhole_;
  std::vector<double> x_of_u_, y_of_v_;
};

}  // namespace

std::vector<Eigen::Vector3d> DepthToPoints(const DepthImage& depth_m, const PinholeCamera& camera,
                                           std::vector<Eigen::Vector2i>* pixels) {
  MOCAP_CHECK(depth_m.width == camera.width && depth_m.height == camera.height, "depth ", depth_m.width, "x",
              depth_m.height, " does not match camera ", camera.width, "x", camera.height);
  const PixelRays rays(camera, depth_m.width, depth_m.height);
  std::vector<Eigen::Vector3d> points;
  points.reserve(depth_m.data.size() / 2);
  if (pixels) pixels->clear();
  for (int v = 0; v < depth_m.height; ++v) {
    for (int u = 0; u < depth_m.width; ++u) {
      const float z = depth_m.at(u, v);
      if (!(z > 0.0f)) continue;
      points.push_back(rays.Point(u, v, z));
      if (pixels) pixels->emplace_back(u, v);
    }
  }
  return points;
}

std::vector<Eigen::Vector3d> DepthToPointsMasked(const DepthImage& depth_m, const PinholeCamera& camera,
                                                 const LabelImage& mask, uint16_t label) {
  MOCAP_CHECK(mask.width == depth_m.width && mask.height == depth_m.height, "mask size differs from depth size");
  MOCAP_CHECK(label != 0, "label 0 is the background");
  const PixelRays rays(camera, depth_m.width, depth_m.height);
  std::vector<Eigen::Vector3d> points;
  for (int v = 0; v < depth_m.height; ++v)
    for (int u = 0; u < depth_m.width; ++u) {
      const float z = depth_m.at(u, v);
      if (mask.at(u, v) == label && z > 0.0f) points.push_back(rays.Point(u, v, z));
    }
  return points;
}

}  // namespace mocap
