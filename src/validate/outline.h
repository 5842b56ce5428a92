#pragma once
// An estimate along the directions no surface normal constrains (a table top's slide in its plane, a box's
// slide along the edge of its two faces), from the object's outline in the measured depth.
//
// The point-to-plane refinement (observability.h) leaves such a direction where the acquisition's
// point-to-point fit stopped, and that fit sees the scene cut by the label's own mask: a label slid a
// centimetre past the table's edge cuts the real table at its own edge, so the fit stays near the label.
// Here the pose is moved along the direction to where the model's outline and the depth's agree, over a
// band of pixels on both sides of the label's outline: the cost at a pose is the area where the model
// covers no measured surface (its points over the floor: model over nothing) plus the area where the
// measured surface lies outside the model's silhouette (the real table's strip the model no longer
// covers). Both are counted at pixel resolution: the first by each crop point's own pixel depth, the
// second by carrying each measured point to the label pose and reading the label's rendered mask there
// (the mask is the model's silhouette at the label pose). The direction is judged when the cost rises on
// both sides of its minimum: an outline that bounds the slide one way only leaves it unobservable.
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "core/rigid3.h"
#include "validate/model_crop.h"
#include "validate/observability.h"

namespace mocap {

/// The frame as the outline estimate reads it; every pointer must outlive the call.
struct OutlineFrame {
  const DepthImage* depth_m = nullptr;      ///< measured depth, registered to `camera`
  const PinholeCamera* camera = nullptr;
  const LabelImage* mask = nullptr;         ///< the check's mask (occluders in front cut to 0)
  const LabelImage* label_mask = nullptr;   ///< the label run's mask, rendered at T_camera_object_label
  uint16_t label_id = 0;
  Rigid3d T_camera_object_label;            ///< where `label_mask` was drawn (the label as labelled)
  const CropSource* model = nullptr;        ///< crops of the whole model (not clipped by the frame)
  double occluder_margin_m = 0.03;          ///< ValidateOptions::occluder_margin_m
  /// The depth's range to this object is biased along the ray (objects.yaml `tof_range_biased` seen by a
  /// time-of-flight camera): its estimate is fitted with that push (validate/range_push.h), or, where none
  /// is found, its position across the ray is taken from the outline too (EstimateAlongOutline).
  bool range_biased = false;
  /// The time-of-flight camera's centre in `camera`'s frame, where the rays the bias lies along start
  /// (a Kinect v2's depth camera sits beside its colour camera).
  Eigen::Vector3d tof_center_camera = Eigen::Vector3d::Zero();
};

struct OutlineOptions {
  /// The line search along each direction: offsets within +-search_m of the estimate (RMS displacement
  /// over the crop), every step_m; the pixels compared lie within search_m (at the object's range) of
  /// the label's outline.
  double search_m = 0.03;
  double step_m = 0.0025;
  /// A measured point counts as the object's surface when within this of the model (along the ray for a
  /// crop point's own pixel): wide enough for a Kinect's depth steps at 2 m, far narrower than the drop
  /// from a table top to the floor.
  double surface_gate_m = 0.03;
  /// The direction is judged when moving the estimate probe_m (ObservabilityOptions) either way raises
  /// the cost by this share of the visible crop and by probe_min_lost_points crop points.
  double min_rise = 0.03;
  /// Pixels of the band compared per direction, at most (every k-th kept).
  int max_pixels = 1500;
  void check() const;
};

/// What the outline estimate did along one direction.
struct OutlineStep {
  int direction = -1;          ///< column of Observability::directions; across the ray: 0 the image's x, 1 its y
  bool across_ray = false;     ///< a move across the camera's ray (OutlineFrame::range_biased)
  double shift_m = 0.0;        ///< the move applied (0 when not judged)
  double rise = 0.0;           ///< the smaller of the two rises, as a share of the visible crop
  bool judged = false;
};

/// For each slide of `o` that no normal constrains (information below kMinProbedInformation), moves
/// `T_camera_object` to the outline's best agreement when the outline bounds it both ways, and judges it
/// by the outline alone (replacing the probe's judgement and probe_loss); a turn no normal constrains is
/// left unjudged. Returns the steps made, one per such slide. `o`'s summary sentences are renewed.
///
/// With `across_ray` (a range-biased object whose estimate is a rigid fit: the range push fit found no
/// push), the estimate is then moved across the time-of-flight camera's ray through the analysis centre,
/// along the image's x and then its y, to the minimum of the model's side of the cost (crop points over no
/// measured surface) wherever that bounds the move both ways (two more steps, `across_ray`). A
/// time-of-flight camera's multipath error lies in each pixel's range, not in which pixels see the object,
/// so the outline is not biased where the rigid fit of the deformed surface is (it shifts sideways as well
/// as back). An estimate fitted with its push is not biased that way, and the outline, which loses the
/// object's grazing pixels, would only add its own error. These moves judge nothing: the directions stay
/// as the analysis found them.
std::vector<OutlineStep> EstimateAlongOutline(const OutlineFrame& frame, const OutlineOptions& options,
                                              const ObservabilityOptions& observability, Rigid3d* T_camera_object,
                                              Observability* o, bool across_ray = false);

}  // namespace mocap
