#pragma once
// The per-frame, per-object label check: an independent SegICP pose from the measured depth, its errors
// against the label (the paper's three: position, rotation axis, rotation angle), the paper's success
// criterion, the alignment score of the label pose itself, and a verdict with its reason.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "validate/acquisition.h"
#include "validate/frame_visibility.h"
#include "validate/observability.h"
#include "validate/tracker.h"
#include "validate/validate_options.h"

namespace mocap {

enum class Verdict { kAccept, kSuspect, kReject };
std::string_view ToString(Verdict verdict);

enum class VerdictReason {
  kAgrees,               ///< estimate reliable and within the accept thresholds of the label
  kAgreesWhereObservable,  ///< as kAgrees in the directions the depth constrains; others unobservable
  kDiffers,              ///< estimate reliable, between the accept and reject thresholds
  kDisagrees,            ///< estimate reliable, beyond the reject thresholds
  kNoReliableEstimate,   ///< no hypothesis reached epsilon; the label's own score is not low
  kLabelDoesNotFit,      ///< no reliable estimate and the label's own score is below reject_label_score
  kNoDepth,              ///< the frame has no depth image
  kMaskSizeMismatch,     ///< the mask and depth sizes differ
  kEmptyMask,            ///< no pixel carries the object's label
  kTooFewPoints,         ///< too few valid depth points under the mask, or supporting the estimate
  kUnreadableInput,      ///< the frame's depth or mask file is missing or cannot be read
  /// Accepted on its own, but the session's records together show this label's camera mount off
  /// (pipeline/session_wide.h): every label of that camera carries the error.
  kCameraMountOff,
  /// Accepted on its own, but the session's records together show this object's mount off by more than
  /// the widest per-record bounds (pipeline/session_wide.h): every label of that object carries it.
  kObjectMountOff,
};
std::string_view ToString(VerdictReason reason);
/// True for the reasons given when the input could not be checked (no estimate was attempted).
bool IsBadInput(VerdictReason reason);

/// The paper's three errors of an estimate against a reference pose.
struct PoseErrors {
  double position_mm = 0.0;
  double rotation_axis_deg = 0.0;   ///< angle between the two rotation axes
  double rotation_angle_deg = 0.0;  ///< angle of the relative rotation
};
PoseErrors ComputePoseErrors(const Rigid3d& estimate, const Rigid3d& reference);

struct LabelCheck {
  Verdict verdict = Verdict::kSuspect;
  VerdictReason reason_code = VerdictReason::kNoReliableEstimate;
  std::string reason;                ///< one line for reports
  int scene_points = 0;              ///< after thinning
  /// Pixels of the object's mask its measured depth showed to be something in front (CutOccluders),
  /// left out of the scene cloud and the crops.
  int64_t occluder_pixels = 0;
  bool estimated = false;            ///< SegICP produced a pose (reliable or not)
  Rigid3d T_camera_object_segicp;
  double segicp_score = 0.0;         ///< a(M, S) of the estimate
  bool segicp_reliable = false;      ///< segicp_score >= epsilon
  PoseErrors errors;                 ///< estimate vs label (meaningful when estimated)
  bool success = false;              ///< the paper's criterion: < 5 cm and < 15 deg (options)
  double label_score = 0.0;          ///< a(M, S) of the crop visible at the label pose
  IcpResult icp;                     ///< the registration that produced the estimate
  /// Which directions the depth constrains at the estimate (validate/observability.h), and the label's
  /// difference from the estimate in those directions; the verdict judges that difference when some
  /// direction is unobservable.
  Observability observability;
  /// The outline estimate's steps along directions no normal constrains (validate/outline.h); empty
  /// when it did not run.
  std::vector<OutlineStep> outline;
  /// For an object whose range the depth pushes back (tof_range_biased on a time-of-flight camera): the
  /// push at grazing incidence fitted with the estimate (validate/range_push.h), mm; 0 otherwise.
  double range_push_mm = 0.0;
  ObservedDifference observed;
  /// The estimate's precision in the judged directions and the accept bounds derived from it (at most
  /// VerdictOptions' accept_*; those when the analysis did not run), mm and deg; set by DecideVerdict.
  EstimatePrecision precision;
  double accept_position_mm = 0.0;
  double accept_rotation_deg = 0.0;
  /// What the depth image cannot resolve at the object, added to the accept floor (ApplyDepthResolution;
  /// 0 until set), mm and deg.
  double resolution_position_mm = 0.0;
  double resolution_rotation_deg = 0.0;
  /// The verdict judged `observed`: the analysis ran and found some direction unobservable.
  bool judged_where_observable() const { return observability.analysed && observability.observable < 6; }
};

/// The label's difference from the estimate that the verdict judges: the observable part when some
/// direction is unobservable (`observed`), else the whole (`errors`): position mm, rotation angle deg.
ObservedDifference JudgedDifference(const LabelCheck& c);

/// Checks one label against the object's scene cloud (camera frame, from the mask). Runs the acquisition
/// (seeded as options.check_seed says; `view_crops` are used for the view-sphere seed). `label_model`:
/// the crops the label's own score takes (null: `model`): the frame's mask as given where `model` and the
/// scene are cut by the depth (CutOccluders), so that a label behind the object's measured surface, whose
/// object the cut takes for something in front, still scores low.
/// `outline`: the frame, when its mask is the label run's (rendered at the label pose), for the estimate
/// along directions only the outline constrains (validate/outline.h); null: those keep the fit's estimate.
LabelCheck CheckLabel(const PointCloud& scene_camera, const Rigid3d& T_camera_object_label, const CropSource& model,
                      const std::vector<ModelCrop>& view_crops, const ValidateOptions& options,
                      const CropSource* label_model = nullptr, const OutlineFrame* outline = nullptr);

/// Same, with the estimate of a tracker that already ran on this frame (the sequence mode): `track` is
/// the step the tracker made on the same `scene_camera` with the same `model` and options. Its index of
/// the scene and its converged point-to-plane refinement, when it kept them (TrackStep), are used
/// instead of being made again.
LabelCheck CheckLabelWithTrack(const PointCloud& scene_camera, const Rigid3d& T_camera_object_label,
                               const CropSource& model, const TrackStep& track, const ValidateOptions& options,
                               const CropSource* label_model = nullptr, const OutlineFrame* outline = nullptr);

/// A frame's mask as the label run drew it: the model's silhouette at `T_camera_object`, which the
/// outline estimate reads (validate/outline.h).
struct MaskAtLabel {
  Rigid3d T_camera_object;    ///< where it was drawn: the label as labelled, before a move to the depth's time
  bool range_biased = false;  ///< OutlineFrame::range_biased
  Eigen::Vector3d tof_center_camera = Eigen::Vector3d::Zero();  ///< OutlineFrame::tof_center_camera
};

/// From a frame: the object's scene cloud is cut from `depth_m` by `mask == label_id`. Bad input (no
/// depth, a mask of another size, an empty mask, too few points) gives a suspect verdict with the
/// reason, never an exception or a crash. With `mask_at_label`, `mask` is the label run's and the
/// outline estimate runs; without, it is a user's mask and it does not.
LabelCheck CheckLabelInFrame(const DepthImage& depth_m, const PinholeCamera& camera, const LabelImage& mask,
                             uint16_t label_id, const Rigid3d& T_camera_object_label, const CropSource& model,
                             const std::vector<ModelCrop>& view_crops, const ValidateOptions& options,
                             const MaskAtLabel* mask_at_label = nullptr);

/// The input checks of CheckLabelInFrame alone: a suspect LabelCheck naming the problem (no depth, sizes
/// differ, empty mask), or nullopt when the object's cloud can be cut from the frame.
std::optional<LabelCheck> CheckFrameInput(const DepthImage& depth_m, const PinholeCamera& camera,
                                          const LabelImage& mask, uint16_t label_id);

/// The frame's object mask cut by its measured depth at the label's pose (CutOccluders with the label's
/// crop from `model`, options.crop.pixel_m and options.occluder_margin_m); nullopt when nothing is cut or
/// the margin is 0 (the paper's plain mask). Input as CheckFrameInput accepts it.
std::optional<OccluderCut> CutOccludersAtLabel(const DepthImage& depth_m, const PinholeCamera& camera,
                                               const LabelImage& mask, uint16_t label_id,
                                               const Rigid3d& T_camera_object_label, const CropSource& model,
                                               const ValidateOptions& options);

/// One object in one frame as the checks see it: its mask cut by the measured depth at the label's pose
/// (CutOccludersAtLabel), its scene cloud and crops through that mask (VisibleInFrameCropSource; `model`
/// itself when options.occluder_margin_m is 0), and, when something was cut, the crops through the mask
/// as given, for the label's own score (CheckLabel's `label_model`). The per-frame and the tracked checks
/// both take it. Its arguments must outlive it; not copyable (its crop sources point into it).
class ObjectInFrame {
 public:
  ObjectInFrame(const DepthImage& depth_m, const PinholeCamera& camera, const LabelImage& mask, uint16_t label_id,
                const Rigid3d& T_camera_object_label, const CropSource& model, const ValidateOptions& options);
  ObjectInFrame(const ObjectInFrame&) = delete;
  ObjectInFrame& operator=(const ObjectInFrame&) = delete;
  /// The object's depth points (camera frame, unthinned) under the cut mask.
  PointCloud SceneCloud() const;
  const CropSource& crops() const { return filter_crops_ ? visible_ : model_; }
  const CropSource* label_crops() const { return cut_ ? &as_masked_ : nullptr; }
  /// The frame for the outline estimate, its mask as the label run drew it.
  OutlineFrame Outline(const MaskAtLabel& drawn) const;
  int64_t occluder_pixels() const { return cut_ ? cut_->pixels : 0; }

 private:
  const DepthImage& depth_m_;
  const PinholeCamera& camera_;
  const LabelImage& label_mask_;  // as given
  uint16_t label_id_;
  double occluder_margin_m_;
  const CropSource& model_;
  bool filter_crops_;
  const std::optional<OccluderCut> cut_;  // before the sources, which see its mask
  const LabelImage& mask_;                // cut_'s mask or the one given
  const VisibleInFrameCropSource visible_, as_masked_;
};

/// A suspect LabelCheck for input that cannot be checked (`code` is one of the bad-input reasons).
LabelCheck BadInputCheck(VerdictReason code, std::string reason, int scene_points = 0);

/// The verdict rules alone (docs/validation.md "Verdicts"); fills verdict, reason_code, reason.
void DecideVerdict(const VerdictOptions& options, LabelCheck* check);

/// A rotational symmetry of an object: rotations about the axis (continuous: by any angle, a body of
/// revolution such as a funnel; discrete: by multiples of step_deg, such as a table's 180 deg) leave its
/// surface unchanged, so depth cannot tell them apart (objects.yaml `symmetries`, docs/objects.md).
struct SymmetryAxis {
  Eigen::Vector3d axis_object = Eigen::Vector3d::UnitZ();   ///< direction, object frame (normalised here)
  Eigen::Vector3d point_object = Eigen::Vector3d::Zero();   ///< a point on the axis, object frame, metres
  double step_deg = 0.0;  ///< 0: continuous; else the discrete step, 360 / step_deg an integer >= 2
};

/// The one symmetry the validator compares modulo, from an object's list (objects.yaml order): the first
/// continuous one, else the first discrete one, else none. A continuous symmetry contains every discrete
/// one about the same axis; about different axes only one can be applied.
std::optional<SymmetryAxis> ChooseValidatorSymmetry(const std::vector<SymmetryAxis>& symmetries);

/// T_camera_object rotated about the object's symmetry axis (by an allowed angle) to the pose nearest in
/// rotation to T_camera_object_reference (an equally valid pose of a symmetric object).
Rigid3d NearestSymmetricPose(const Rigid3d& T_camera_object, const Rigid3d& T_camera_object_reference,
                             const SymmetryAxis& symmetry);

/// Compares a check's SegICP estimate with the label modulo `symmetry`: the estimate is replaced by its
/// symmetric equivalent nearest to the label, then errors, success and verdict are recomputed. No-op
/// without an estimate.
void ApplySymmetry(const Rigid3d& T_camera_object_label, const SymmetryAxis& symmetry, const ValidateOptions& options,
                   LabelCheck* check);

/// A time-of-flight camera measures the range to a reflective surface too long (multipath adds path:
/// Bhandari et al., "Resolving multipath interference in Kinect"; the SegICP paper's oil bottle on the
/// Kinect v2), so for an object declared so (objects.yaml `tof_range_biased`) the estimate's translation
/// along the time-of-flight camera's ray through the analysis centre is not judged; every other
/// direction is. That ray starts at `tof_center_camera`, the depth camera's centre in the check's camera
/// frame (a Kinect v2's depth camera sits beside the colour camera the labels are in). Errors and verdict
/// are recomputed; the reason says so. No-op without an estimate or an analysis.
void LeaveOutRange(const Rigid3d& T_camera_object_label, const Eigen::Vector3d& tof_center_camera,
                   const ValidateOptions& options, LabelCheck* check);

/// The depth image's resolution at an object: the footprint of one depth pixel across the ray and the
/// smallest change of depth the camera reports along it, metres.
struct DepthResolution {
  double pixel_m = 0.0;
  double step_m = 0.0;
};

/// No fit to a depth image pins an object closer than its resolution: a surface that stays within one
/// disparity step, an outline that falls within one pixel, reads the same wherever in it the object lies,
/// and the rounding does not average out when the whole surface rounds the same way. A Kinect v1's step
/// grows as the square of the range (kinect.md section 8: 2.85e-3 z^2, 14 mm at 2.2 m), so far away this,
/// not the noise, limits the estimate. The record's accept floor therefore takes half a pixel and half a
/// step in position (hypot), and half a pixel at the analysis's RMS radius in rotation, beside the label's
/// own error; the verdict is decided again. No-op without an estimate or an analysis.
void ApplyDepthResolution(const DepthResolution& resolution, const ValidateOptions& options, LabelCheck* check);

}  // namespace mocap
