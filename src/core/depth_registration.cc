#include "core/depth_registration.h"

#include <algorithm>
#include <cmath>

namespace mocap {

DepthImage RegisterDepthToColor(const DepthImage& depth_m, const PinholeCamera& depth_camera,
                                const PinholeCamera& color_camera, const Rigid3d& T_color_depth) {
  DepthImage out(color_camera.width, color_camera.height, 0.0f);
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
      for (int y = v0; y <= v1; ++y)
        for (int x = u0; x <= u1; ++x) {
          float& d = out.at(x, y);
          if (d == 0.0f || z_color < d) d = z_color;
        }
    }
  return out;
}

}  // namespace mocap
