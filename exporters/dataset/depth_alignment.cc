// ColorAlignedDepthM: BOP and TUM assume depth aligned with the colour image (formats.md §1, §6), which
// a Kinect v2 does not deliver (its 512x424 depth camera sits beside the 1920x1080 colour camera).
#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>

#include "exporters/dataset/dataset.h"

namespace mocap::exporters {
namespace {

cv::Mat ToMat(const DepthImage& depth_m) {
  cv::Mat out(depth_m.height, depth_m.width, CV_32FC1);
  std::copy(depth_m.data.begin(), depth_m.data.end(), out.ptr<float>());
  return out;
}

/// Forward-warps every valid depth pixel into the colour image. Each depth pixel covers about
/// (f_colour / f_depth)^2 colour pixels, so it is splatted over that footprint (rounded up) with a
/// z-test: the nearest surface wins, as a registered sensor would see it; pixels no depth pixel reaches
/// stay 0 (no depth), never interpolated.
cv::Mat Reproject(const DepthImage& depth_m, const PinholeCamera& depth_camera, const PinholeCamera& color_camera,
                  const Rigid3d& T_color_depth) {
  cv::Mat out = cv::Mat::zeros(color_camera.height, color_camera.width, CV_32FC1);
  const double scale_u = color_camera.fx / depth_camera.fx, scale_v = color_camera.fy / depth_camera.fy;
  for (int v = 0; v < depth_m.height; ++v)
    for (int u = 0; u < depth_m.width; ++u) {
      const float z = depth_m.at(u, v);
      if (!(z > 0)) continue;
      const Eigen::Vector3d p_color = T_color_depth * depth_camera.Unproject(Eigen::Vector2d(u, v), z);
      const auto pixel = color_camera.Project(p_color);
      if (!pixel) continue;
      const float z_color = static_cast<float>(p_color.z());
      const double half_u = 0.5 * scale_u * z / z_color, half_v = 0.5 * scale_v * z / z_color;
      const int u0 = std::max(0, static_cast<int>(std::lround(pixel->x() - half_u)));
      const int u1 = std::min(color_camera.width - 1, static_cast<int>(std::lround(pixel->x() + half_u)));
      const int v0 = std::max(0, static_cast<int>(std::lround(pixel->y() - half_v)));
      const int v1 = std::min(color_camera.height - 1, static_cast<int>(std::lround(pixel->y() + half_v)));
      for (int y = v0; y <= v1; ++y) {
        float* row = out.ptr<float>(y);
        for (int x = u0; x <= u1; ++x)
          if (row[x] == 0.0f || z_color < row[x]) row[x] = z_color;
      }
    }
  return out;
}

}  // namespace

cv::Mat ColorAlignedDepthM(const ExportScene& scene, const ExportFrame& frame) {
  if (frame.depth_path.empty()) return {};
  const DepthImage depth_m = scene.session->LoadDepth(scene.camera, frame.index);
  if (scene.depth_registered_to_color) return ToMat(depth_m);
  return Reproject(depth_m, scene.depth_camera, scene.color_camera, scene.T_color_depth);
}

}  // namespace mocap::exporters
