#pragma once
// Model crops as a real frame sees them: the crop of the wrapped source minus the points that something
// else in front hides (a pixel outside the object's mask whose measured depth is nearer than the point by
// more than a margin), that fall on a labelled pixel without measured depth (this object's or an
// occluder's surface nearer than the sensor's range, dark or shiny: no depth to compare) or that fall
// outside the image. Depthless background pixels keep their points: they carry the outline. Without this, an object half hidden behind another scores about half, whatever its pose: the
// scene cloud holds only its visible part, and a(M, S) counts every crop point.
#include <cmath>
#include <cstdint>
#include <optional>

#include "core/camera.h"
#include "core/image.h"
#include "core/pinhole.h"
#include "validate/model_crop.h"

namespace mocap {

/// The pixel index nearest to coordinate x, halves away from zero: std::lround without the libm call,
/// which x86-64 without SSE4.1 does not inline and a crop makes per point. |x| >= 1e9 (a point grazing
/// the camera plane) gives -1, which no image contains.
inline int NearestPixel(double x) {
  if (!(std::abs(x) < 1e9)) return -1;
  const int whole = static_cast<int>(x);  // toward zero
  const double rest = x - whole;           // exact
  return whole + (rest >= 0.5) - (rest <= -0.5);
}

/// The pixel index nearest to camera-frame point p's projection, or nullopt behind the camera (or where a
/// distorted projection fails); not checked against the image. `pinhole` is !camera.has_distortion(),
/// decided once per loop (the call is out of line): then Project's arithmetic runs inline (core/pinhole.h:
/// the same pixels).
inline std::optional<Eigen::Vector2i> NearestPixelOf(const PinholeCamera& camera, bool pinhole, const Eigen::Vector3d& p) {
  if (pinhole) {
    if (!(p.z() > 0)) return std::nullopt;
    const Eigen::Vector2d pixel = ProjectWithoutDistortion(camera, p);
    return Eigen::Vector2i(NearestPixel(pixel.x()), NearestPixel(pixel.y()));
  }
  const auto pixel = camera.Project(p);
  if (!pixel) return std::nullopt;
  return Eigen::Vector2i(NearestPixel(pixel->x()), NearestPixel(pixel->y()));
}

class VisibleInFrameCropSource : public CropSource {
 public:
  /// `base`, `camera`, `depth_m` and `mask` must outlive this source; `T_camera_model` of each crop is in
  /// this camera. A point is hidden when its pixel is not the object's (mask != label_id) and the measured
  /// depth there is valid and nearer than the point's z by more than `occluder_margin_m`. Pixels of the
  /// object itself never hide it, so a label behind the object's measured surface keeps all its points
  /// and scores low. Precondition: depth, mask and camera have the same size.
  VisibleInFrameCropSource(const CropSource& base, const PinholeCamera& camera, const DepthImage& depth_m,
                           const LabelImage& mask, uint16_t label_id, double occluder_margin_m);
  ModelCrop Crop(const Rigid3d& T_camera_model) const override;
  ModelCrop CropPoints(const Rigid3d& T_camera_model) const override;
  const PointCloud& surface_model() const override { return base_.surface_model(); }

 private:
  /// `crop` (the base source's at T_camera_model) less the points this frame cannot see.
  ModelCrop Visible(const Rigid3d& T_camera_model, ModelCrop crop) const;

  const CropSource& base_;
  const PinholeCamera& camera_;
  const DepthImage& depth_m_;
  const LabelImage& mask_;
  uint16_t label_id_;
  double margin_m_;
};

/// The object's pixels as the frame's measured depth shows them: the label's mask is rendered from the
/// known objects alone, so a hand or a tool between camera and object lies inside it, and its points would
/// be taken for the object's.
struct OccluderCut {
  LabelImage mask;     ///< the given mask with the cut pixels set to 0 (background)
  int64_t pixels = 0;  ///< pixels of the object cut
};

/// Cuts from `mask` the pixels of `label_id` whose measured depth is nearer than the label's model surface
/// there by more than `margin_m`. The model surface at a pixel is the nearest point of `label_crop` (the
/// crop at the label's pose, its T_camera_model) projecting into the pixel's cell or the eight around it;
/// a cell is one crop point's footprint at the crop's nearest depth (`crop_pixel_m` across), so an object
/// pixel has crop points about it, and the nearest of nine cells errs toward keeping a pixel. A label a
/// centimetre or two off still keeps the object's own points: only what lies `margin_m` before its surface
/// goes. Pixels without depth or without a crop point about them are kept. nullopt when nothing is cut (or
/// the crop is empty). Precondition: depth, mask and camera have the same size.
std::optional<OccluderCut> CutOccluders(const DepthImage& depth_m, const PinholeCamera& camera, const LabelImage& mask,
                                        uint16_t label_id, const ModelCrop& label_crop, double crop_pixel_m,
                                        double margin_m);

}  // namespace mocap
