#pragma once
// The undistorted pinhole grid that is actually rasterised for a camera, with a margin around the image:
//  - the margin lets bbox_obj and px_count_all include parts of an object outside the image (BOP renders
//    on a 3x canvas with a shifted principal point for the same reason: formats.md §1);
//  - with lens distortion, the canvas covers the undistorted positions of every image pixel, and a
//    per-pixel lookup (nearest neighbour, so labels are never blended) maps it onto the distorted image.
//    The lookup is computed once per camera.
#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "render/conventions.h"

namespace mocap {

/// A rectangle of pixels [x, x + width) x [y, y + height).
struct PixelRect {
  int x = 0, y = 0, width = 0, height = 0;
  bool empty() const { return width <= 0 || height <= 0; }
  bool contains(int u, int v) const { return u >= x && v >= y && u < x + width && v < y + height; }
  PixelRect Intersect(const PixelRect& other) const;
};

class RenderCanvas {
 public:
  /// `outside_margin_fraction`: margin on each side as a fraction of the image size (1.0 = BOP's 3x
  /// canvas). Precondition: camera.check() passes, fraction >= 0.
  RenderCanvas(const PinholeCamera& camera, double outside_margin_fraction);

  const PinholeCamera& camera() const { return camera_; }
  const CanvasIntrinsics& intrinsics() const { return canvas_; }
  PixelRect bounds() const { return {0, 0, canvas_.width, canvas_.height}; }
  bool distorted() const { return distorted_; }

  /// Canvas pixel seen by image pixel (u, v) (nearest), as an index y * width + x, or -1.
  int32_t CanvasIndexOfImagePixel(int u, int v) const;
  /// Image pixel position (OpenCV convention, may lie outside the image) of canvas pixel (x, y);
  /// false where the distortion model is not valid there (far outside the calibrated field of view).
  bool ImagePositionOfCanvasPixel(int x, int y, double& u, double& v) const;
  /// Whether canvas pixel (x, y) is seen by some image pixel.
  bool InsideImage(int x, int y) const;
  /// Image pixels whose canvas pixel lies in `canvas_rect` (a superset, clamped to the image).
  PixelRect ImageRectOf(const PixelRect& canvas_rect) const;

 private:
  PinholeCamera camera_;
  CanvasIntrinsics canvas_;
  bool distorted_ = false;
  int offset_x_ = 0, offset_y_ = 0;  // canvas pixel of image pixel (0, 0) without distortion
  double max_radius2_ = 0;           // squared normalised radius up to which the distortion model is used
  std::vector<int32_t> lookup_;      // per image pixel, with distortion
  std::vector<uint8_t> inside_;      // per canvas pixel, with distortion
};

/// True when the cameras have identical size, intrinsics and distortion.
bool SameCamera(const PinholeCamera& a, const PinholeCamera& b);

}  // namespace mocap
