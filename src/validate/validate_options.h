#pragma once
// All settings of the SegICP validator in one struct, the paper's values as defaults
// (docs/validation.md lists each with its source).
#include "validate/acquisition.h"
#include "validate/alignment_score.h"
#include "validate/crop_cache.h"
#include "validate/icp.h"
#include "validate/observability.h"
#include "validate/outline.h"
#include "validate/model_crop.h"
#include "validate/pose_filter.h"
#include "validate/range_push.h"

namespace mocap {

struct TrackingOptions {
  /// Below this score the filter only propagates and the object goes back to acquisition (the
  /// paper's theta; its value is not given there).
  double theta = 0.5;
  /// Scene points farther than this outside the model's bounding box at the predicted pose are pruned
  /// ("removing points outside a bounding box of the latest registered model pose").
  double box_margin_m = 0.02;
  /// The session check runs an acquisition instead of a tracking step at every frame whose index is a
  /// multiple of this (seeded by the label): a cross-check against a track settled on a wrong minimum,
  /// and a fresh start at fixed frames, so validation shards that begin at such frames merge into
  /// what one pass writes. 0: acquisitions only at the start and after a failed step.
  int reacquire_every = 30;
  /// Tracking assumes consecutive frames: after a longer gap since the tracker's last frame it acquires
  /// instead (sparse frames seconds apart, such as LM-O's, or a long stretch of bad input), seconds.
  double max_gap_s = 0.5;
  /// When the frame's prior (the label) lies farther than this from the track's prediction the tracker
  /// acquires (seeded by the prior) instead of tracking: frames that are not a sequence (LM-O's images
  /// carry stamps 1/30 s apart), or a track gone astray. A wrong label within these bounds is still
  /// tracked and compared; beyond them its acquisition finds where the object is.
  double max_prior_distance_m = 0.03;
  double max_prior_angle_deg = 15.0;
  /// A tracking step's agreement stands only when the label's difference lies within this fraction of
  /// the accept bounds; a closer call, like a disagreement, is checked again by a full acquisition. A
  /// track carries its start's estimate along directions the surface barely constrains (a bottle's
  /// spin), so near the bound a tracked estimate is weaker evidence than an acquisition. Chosen on the
  /// accuracy sweep against the cost of the re-checks (docs/validation.md, parameters).
  double confirm_fraction = 0.7;
  /// The tracking step is point-to-plane from the prediction in the observable directions
  /// (RefinePointToPlane, observability.refine_iterations); its first correspondence gate, metres.
  double initial_gate_m = 0.02;
  /// A point-to-point tracking step (AlignPointToPoint from the prediction; bench_validate's kernel, with
  /// PCL's beside it). Tight convergence: point-to-point ICP slides slowly along planar faces, and a
  /// loose stop leaves millimetres of slide in the pose.
  IcpOptions icp = [] {
    IcpOptions o;
    o.initial_correspondence_distance_m = 0.02;
    o.max_iterations = 40;
    o.source_stride = 2;
    o.translation_epsilon_m = 2e-5;
    o.rotation_epsilon_deg = 0.005;
    return o;
  }();
  void check() const;
};

/// Thresholds of the label verdict (docs/validation.md "Verdicts").
struct VerdictOptions {
  /// SegICP estimate and label agree: accept. These are the widest accept bounds; each record's own
  /// are sqrt(floor^2 + (accept_sigmas * sigma)^2), at most these, sigma the estimate's precision in the
  /// judged directions (PrecisionOf; docs/validation.md "Accept bounds"). The floor stands for the
  /// label's own error (tracker noise, calibration residuals), which the depth cannot tell apart.
  double accept_position_m = 0.005;
  double accept_rotation_deg = 3.0;
  double accept_floor_position_m = 0.0025;
  double accept_floor_rotation_deg = 1.5;
  double accept_sigmas = 3.0;
  /// Supported crop points per independent residual in PrecisionOf.
  double points_per_residual = 4.0;
  /// SegICP estimate and label disagree beyond these: reject.
  double reject_position_m = 0.02;
  double reject_rotation_deg = 10.0;
  /// The paper's success criterion for the estimate against the label (errors below both).
  double success_position_m = 0.05;
  double success_rotation_deg = 15.0;
  /// Without a reliable estimate, a label whose own alignment score falls below this is rejected.
  double reject_label_score = 0.3;
  /// An estimate the depth supports with fewer model points than this (Observability::supported_points)
  /// checks nothing: the label is `too_few_points`, as when the mask holds too few depth points. Six
  /// degrees of freedom fitted to a few dozen noisy points follow the noise and whatever else lies in
  /// the mask (docs/validation.md "Too few points").
  int min_supported_points = 30;
  void check() const;
};

/// How label checks seed the acquisition.
enum class AcquisitionSeed {
  kViewSphere,  ///< the paper: crops on a view sphere, independent of the label
  kLabel,       ///< hypotheses spread about the label's orientation (AcquireAround)
};

struct ValidateOptions {
  /// Scene clouds are thinned to one point per voxel of this edge before registration, metres.
  double scene_voxel_m = 0.003;
  /// Fewer scene points than this (after thinning) and the object is not checked.
  int min_scene_points = 50;
  /// Checks in a frame drop crop points that the measured depth shows hidden behind something nearer by
  /// more than this (VisibleInFrameCropSource); 0 keeps every crop point (the paper's plain crops).
  double occluder_margin_m = 0.03;
  AcquisitionSeed check_seed = AcquisitionSeed::kLabel;
  AlignmentOptions alignment;
  CropOptions crop;
  /// Crops of the session check come from a cache per object and view (CachedCropSource).
  CropCacheOptions crop_cache;
  AcquisitionOptions acquisition;
  TrackingOptions tracking;
  PoseFilterOptions filter;
  VerdictOptions verdict;
  /// Which directions the depth constrains; the verdict judges only those.
  ObservabilityOptions observability;
  /// The estimate along directions only the object's outline constrains (validate/outline.h).
  OutlineOptions outline;
  /// The estimate of a range-biased object fitted with its push (validate/range_push.h).
  RangePushOptions range_push;
  /// Throws InputError naming the first invalid setting.
  void check() const;
};

}  // namespace mocap
