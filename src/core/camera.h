#pragma once
// Pinhole camera with OpenCV's distortion model and pixel convention (centre of the top-left pixel at
// (0, 0); x right, y down, z forward). Project() reproduces cv::projectPoints (tested against it).
#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

#include "core/image.h"

namespace mocap {

struct PinholeCamera {
  int width = 0;   ///< pixels
  int height = 0;  ///< pixels
  double fx = 0, fy = 0, cx = 0, cy = 0;  ///< pixels
  /// OpenCV order k1 k2 p1 p2 k3 k4 k5 k6 (rational model); unused trailing entries are 0.
  std::array<double, 8> dist{};

  /// Throws InputError when sizes or focal lengths are not positive.
  void check() const;
  bool has_distortion() const;
  Eigen::Matrix3d K() const;

  /// Normalised undistorted coordinates (x/z, y/z) to distorted normalised coordinates.
  Eigen::Vector2d Distort(const Eigen::Vector2d& xy) const;
  /// Inverse of Distort (Newton iterations to 1e-15), within the region where the model is monotonic.
  Eigen::Vector2d Undistort(const Eigen::Vector2d& xy_distorted) const;

  /// Pixel of a point in camera coordinates (metres). Empty when z <= 0.
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& point_camera) const;
  /// Point at depth z (metres, along the optical axis) seen at pixel (u, v).
  Eigen::Vector3d Unproject(const Eigen::Vector2d& pixel, double z_m) const;
  /// Undistorted normalised ray (x, y, 1) through pixel (u, v).
  Eigen::Vector3d Ray(const Eigen::Vector2d& pixel) const;
};

/// Back-projects every valid (depth > 0) pixel; `pixels`, if given, receives the (u, v) of each point.
/// Precondition: depth size equals the camera size.
std::vector<Eigen::Vector3d> DepthToPoints(const DepthImage& depth_m, const PinholeCamera& camera,
                                           std::vector<Eigen::Vector2i>* pixels = nullptr);

/// Same, restricted to pixels where mask(u, v) == label (label != 0).
std::vector<Eigen::Vector3d> DepthToPointsMasked(const DepthImage& depth_m, const PinholeCamera& camera,
                                                 const LabelImage& mask, uint16_t label);

}  // namespace mocap
