#include "render/conventions.h"

#include "core/check.h"

namespace mocap {

Eigen::Matrix4f GlClipFromCamera(const CanvasIntrinsics& canvas, double near_m, double far_m) {
  MOCAP_CHECK(near_m > 0 && far_m > near_m, "clip range ", near_m, "..", far_m, " m");
  MOCAP_CHECK(canvas.width > 0 && canvas.height > 0 && canvas.fx > 0 && canvas.fy > 0, "bad canvas");
  const double w = canvas.width, h = canvas.height;
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  // x_clip = (2 fx / W) x + ((2 cx + 1) / W - 1) z, w_clip = z: dividing by w gives x_ndc above.
  P(0, 0) = 2.0 * canvas.fx / w;
  P(0, 2) = (2.0 * canvas.cx + 1.0) / w - 1.0;
  P(1, 1) = 2.0 * canvas.fy / h;
  P(1, 2) = (2.0 * canvas.cy + 1.0) / h - 1.0;
  P(2, 2) = (far_m + near_m) / (far_m - near_m);
  P(2, 3) = -2.0 * far_m * near_m / (far_m - near_m);
  P(3, 2) = 1.0;
  return P.cast<float>();
}

Eigen::Vector2d PixelFromNdc(const CanvasIntrinsics& canvas, const Eigen::Vector2d& ndc) {
  return {((ndc.x() + 1.0) * canvas.width - 1.0) / 2.0, ((ndc.y() + 1.0) * canvas.height - 1.0) / 2.0};
}

}  // namespace mocap
