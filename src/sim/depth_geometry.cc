#include "sim/depth_geometry.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "core/check.h"

namespace mocap::sim {
namespace {

/// Undistorted normalised x (x/z) of every column of a row.
std::vector<double> NormalisedColumnsX(const PinholeCamera& camera, int v) {
  std::vector<double> x(static_cast<size_t>(camera.width));
  for (int u = 0; u < camera.width; ++u)
    x[static_cast<size_t>(u)] = camera.has_distortion() ? camera.Ray({u, v}).x() : (u - camera.cx) / camera.fx;
  return x;
}

}  // namespace

MaskImage ShadowMask(const DepthImage& depth_m, const PinholeCamera& camera, double baseline_x_m, double tolerance_px) {
  MOCAP_CHECK(depth_m.width == camera.width && depth_m.height == camera.height, "depth and camera sizes differ");
  MaskImage shadow(depth_m.width, depth_m.height, 0);
  if (baseline_x_m == 0.0) return shadow;
  const double tolerance = tolerance_px / camera.fx;
  // Seen from the viewpoint, a surface point at normalised x and depth z sits at x - b / z. Scanning
  // from the side of the viewpoint (b > 0: right to left), visible points keep decreasing (b > 0) or
  // increasing (b < 0) viewpoint coordinates; a point that breaks the order is hidden behind one scanned.
  const bool from_right = baseline_x_m > 0;
#pragma omp parallel for schedule(static)
  for (int v = 0; v < depth_m.height; ++v) {
    const std::vector<double> x = NormalisedColumnsX(camera, v);
    double extreme = from_right ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity();
    for (int step = 0; step < depth_m.width; ++step) {
      const int u = from_right ? depth_m.width - 1 - step : step;
      const float z = depth_m.at(u, v);
      if (!(z > 0)) continue;
      const double x_view = x[static_cast<size_t>(u)] - baseline_x_m / z;
      if (from_right) {
        if (x_view > extreme + tolerance) shadow.at(u, v) = 1;
        extreme = std::min(extreme, x_view);
      } else {
        if (x_view < extreme - tolerance) shadow.at(u, v) = 1;
        extreme = std::max(extreme, x_view);
      }
    }
  }
  return shadow;
}

MaskImage DepthEdgeMask(const DepthImage& depth_m, double jump_fraction, double min_jump_m, int band_px) {
  MOCAP_CHECK(band_px >= 1, "edge band must be at least one pixel");
  MaskImage edge(depth_m.width, depth_m.height, 0);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < depth_m.height; ++v) {
    for (int u = 0; u < depth_m.width; ++u) {
      const float z = depth_m.at(u, v);
      if (!(z > 0)) continue;
      const double threshold = std::max(min_jump_m, jump_fraction * z);
      bool is_edge = false;
      for (int dv = -band_px; dv <= band_px && !is_edge; ++dv) {
        for (int du = -band_px; du <= band_px && !is_edge; ++du) {
          if (!depth_m.contains(u + du, v + dv)) continue;
          const float zn = depth_m.at(u + du, v + dv);
          is_edge = !(zn > 0) || std::abs(zn - z) > threshold;
        }
      }
      edge.at(u, v) = is_edge ? 1 : 0;
    }
  }
  return edge;
}

Image<float> IncidenceAngleImage(const DepthImage& depth_m, const PinholeCamera& camera, double max_step_fraction) {
  Image<float> angle(depth_m.width, depth_m.height, -1.0f);
  auto point = [&](int u, int v) { return camera.Unproject({u, v}, depth_m.at(u, v)); };
  auto usable = [&](int u, int v, float z) {
    if (!depth_m.contains(u, v)) return false;
    const float zn = depth_m.at(u, v);
    return zn > 0 && std::abs(zn - z) <= max_step_fraction * z;
  };
#pragma omp parallel for schedule(static)
  for (int v = 0; v < depth_m.height; ++v) {
    for (int u = 0; u < depth_m.width; ++u) {
      const float z = depth_m.at(u, v);
      if (!(z > 0)) continue;
      // One-sided differences where the central one would cross a discontinuity.
      const int u0 = usable(u - 1, v, z) ? u - 1 : u, u1 = usable(u + 1, v, z) ? u + 1 : u;
      const int v0 = usable(u, v - 1, z) ? v - 1 : v, v1 = usable(u, v + 1, z) ? v + 1 : v;
      if (u0 == u1 || v0 == v1) continue;
      const Eigen::Vector3d normal = (point(u1, v) - point(u0, v)).cross(point(u, v1) - point(u, v0));
      const Eigen::Vector3d sight = point(u, v).normalized();
      if (normal.norm() == 0) continue;
      angle.at(u, v) = static_cast<float>(std::acos(std::min(1.0, std::abs(normal.normalized().dot(sight)))));
    }
  }
  return angle;
}

}  // namespace mocap::sim
