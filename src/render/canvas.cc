#include "render/canvas.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace mocap {

PixelRect PixelRect::Intersect(const PixelRect& o) const {
  const int x0 = std::max(x, o.x), y0 = std::max(y, o.y);
  const int x1 = std::min(x + width, o.x + o.width), y1 = std::min(y + height, o.y + o.height);
  return {x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)};
}

bool SameCamera(const PinholeCamera& a, const PinholeCamera& b) {
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy && a.cx == b.cx &&
         a.cy == b.cy && a.dist == b.dist;
}

RenderCanvas::RenderCanvas(const PinholeCamera& camera, double outside_margin_fraction)
    : camera_(camera), distorted_(camera.has_distortion()) {
  camera.check();
  MOCAP_CHECK(outside_margin_fraction >= 0, "negative margin");
  // Undistorted pixel bounds the canvas must cover: the image plus the outside margin, plus (with
  // distortion) the undistorted position of every border pixel of the image.
  double u0 = -outside_margin_fraction * camera.width, u1 = camera.width - 1 + outside_margin_fraction * camera.width;
  double v0 = -outside_margin_fraction * camera.height, v1 = camera.height - 1 + outside_margin_fraction * camera.height;
  if (distorted_) {
    auto cover = [&](int u, int v) {
      const Eigen::Vector3d ray = camera.Ray({u, v});
      const double x = camera.fx * ray.x() + camera.cx, y = camera.fy * ray.y() + camera.cy;
      u0 = std::min(u0, x - 2), u1 = std::max(u1, x + 2), v0 = std::min(v0, y - 2), v1 = std::max(v1, y + 2);
      max_radius2_ = std::max(max_radius2_, ray.head<2>().squaredNorm());
    };
    for (int u = 0; u < camera.width; ++u) cover(u, 0), cover(u, camera.height - 1);
    for (int v = 0; v < camera.height; ++v) cover(0, v), cover(camera.width - 1, v);
    max_radius2_ *= 1.1;
  }
  offset_x_ = static_cast<int>(-std::floor(u0));
  offset_y_ = static_cast<int>(-std::floor(v0));
  canvas_ = {static_cast<int>(std::ceil(u1)) + offset_x_ + 1, static_cast<int>(std::ceil(v1)) + offset_y_ + 1,
             camera.fx, camera.fy, camera.cx + offset_x_, camera.cy + offset_y_};
  if (!distorted_) return;
  lookup_.resize(static_cast<size_t>(camera.width) * camera.height);
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const Eigen::Vector3d ray = camera.Ray({u, v});
      const auto x = static_cast<int>(std::lround(canvas_.fx * ray.x() + canvas_.cx));
      const auto y = static_cast<int>(std::lround(canvas_.fy * ray.y() + canvas_.cy));
      lookup_[static_cast<size_t>(v) * camera.width + u] = bounds().contains(x, y) ? y * canvas_.width + x : -1;
    }
  }
  inside_.assign(static_cast<size_t>(canvas_.width) * canvas_.height, 0);
  for (int32_t index : lookup_)
    if (index >= 0) inside_[static_cast<size_t>(index)] = 1;
}

int32_t RenderCanvas::CanvasIndexOfImagePixel(int u, int v) const {
  if (distorted_) return lookup_[static_cast<size_t>(v) * camera_.width + u];
  return (v + offset_y_) * canvas_.width + (u + offset_x_);
}

bool RenderCanvas::ImagePositionOfCanvasPixel(int x, int y, double& u, double& v) const {
  if (!distorted_) {
    u = x - offset_x_, v = y - offset_y_;
    return true;
  }
  const Eigen::Vector2d xy((x - canvas_.cx) / canvas_.fx, (y - canvas_.cy) / canvas_.fy);
  if (xy.squaredNorm() > max_radius2_) return false;
  const Eigen::Vector2d d = camera_.Distort(xy);
  u = camera_.fx * d.x() + camera_.cx, v = camera_.fy * d.y() + camera_.cy;
  return true;
}

bool RenderCanvas::InsideImage(int x, int y) const {
  if (distorted_) return inside_[static_cast<size_t>(y) * canvas_.width + x] != 0;
  return x >= offset_x_ && y >= offset_y_ && x < offset_x_ + camera_.width && y < offset_y_ + camera_.height;
}

PixelRect RenderCanvas::ImageRectOf(const PixelRect& r) const {
  const PixelRect image{0, 0, camera_.width, camera_.height};
  if (r.empty()) return {};
  if (!distorted_) return PixelRect{r.x - offset_x_, r.y - offset_y_, r.width, r.height}.Intersect(image);
  // Map the rectangle's border; distortion is monotonic inside the valid radius, so the border's image
  // bounds the interior's. Outside the valid radius, fall back to the whole image.
  double u0 = 1e30, v0 = 1e30, u1 = -1e30, v1 = -1e30;
  auto add = [&](int x, int y) {
    double u, v;
    if (!ImagePositionOfCanvasPixel(x, y, u, v)) return false;
    u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
    return true;
  };
  bool valid = true;
  for (int x = r.x; x < r.x + r.width; ++x) valid = add(x, r.y) && add(x, r.y + r.height - 1) && valid;
  for (int y = r.y; y < r.y + r.height; ++y) valid = add(r.x, y) && add(r.x + r.width - 1, y) && valid;
  if (!valid) return image;
  const int x0 = static_cast<int>(std::floor(u0)) - 1, y0 = static_cast<int>(std::floor(v0)) - 1;
  return PixelRect{x0, y0, static_cast<int>(std::ceil(u1)) + 2 - x0, static_cast<int>(std::ceil(v1)) + 2 - y0}.Intersect(image);
}

}  // namespace mocap
