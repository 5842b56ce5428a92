#include "validate/label_check.h"

#include <algorithm>
#include <cstdio>

#include "core/check.h"
#include "validate/frame_visibility.h"
#include "validate/range_push.h"

namespace mocap {
namespace {

std::string Fixed(double value, int digits) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, value);
  return buffer;
}

/// Errors and success of the estimate against the label.
void ScoreEstimate(const Rigid3d& label, const ValidateOptions& options, LabelCheck* check) {
  check->errors = ComputePoseErrors(check->T_camera_object_segicp, label);
  check->success = check->errors.position_mm < 1e3 * options.verdict.success_position_m &&
                   check->errors.rotation_axis_deg < options.verdict.success_rotation_deg &&
                   check->errors.rotation_angle_deg < options.verdict.success_rotation_deg;
  check->segicp_reliable = check->segicp_score >= options.acquisition.epsilon;
  check->observed = ObservedPart(check->observability, check->T_camera_object_segicp, label);
}


/// Directions the probe alone found observable (weak in the normals, seen by the outline) are refined
/// in a second point-to-plane pass, with the robust kernel: the acquisition's point-to-point ICP leaves a
/// near-body of revolution turned by its clutter (a hand holding a bottle turned it 2 deg), and the first
/// pass moves only along strong directions. Returns whether it moved the estimate (and scored it anew).
bool PolishProbedDirections(const PointGrid& grid, const CropSource& model, const ValidateOptions& options,
                            LabelCheck* check) {
  if (!HasProbedDirections(check->observability)) return false;
  // A crop of its own, not the refinement's: one from the tracking step's prediction slowed the polish.
  const ModelCrop crop = model.Crop(check->T_camera_object_segicp);
  const PlaneRefinement refined =
      RefinePointToPlane(crop, check->T_camera_object_segicp, grid, options.observability, 0.0, &check->observability);
  if (refined.iterations == 0) return false;
  // No score guard: the score counts clutter within tau as support (fingers on a held bottle), which the
  // robust fit rightly ignores, so a better pose can score a few hundredths lower.
  check->T_camera_object_segicp = refined.T_camera_object;
  check->segicp_score = ScoreAlignment(crop.points_model, refined.T_camera_object, grid, options.alignment).score;
  return true;
}

/// The estimate's point-to-plane refinement, which moves it only where the depth constrains it, and the
/// analysis of where that is. `made`: a converged refinement already made against `grid` that ended at
/// the estimate (a tracking step's, with the crop it used), taken instead of refining again.
void RefineEstimate(const PointGrid& grid, const CropSource& model, const ValidateOptions& options,
                    const TrackStep* made, LabelCheck* check) {
  if (made) {
    // Its score is the estimate's score already (the same crop, pose and scene).
    check->observability = ProbeObservability(model, made->refinement_crop, check->T_camera_object_segicp, grid,
                                              options.observability, made->refinement->observability);
    PolishProbedDirections(grid, model, options, check);
    return;
  }
  const ModelCrop crop = model.Crop(check->T_camera_object_segicp);
  const PlaneRefinement refined = RefinePointToPlane(crop, check->T_camera_object_segicp, grid, options.observability);
  if (refined.iterations > 0) check->T_camera_object_segicp = refined.T_camera_object;
  // A converged refinement's last equations are the analysis at its result (within refine_step_m).
  check->observability =
      refined.converged
          ? ProbeObservability(model, crop, check->T_camera_object_segicp, grid, options.observability, refined.observability)
          : AnalyseObservability(model, check->T_camera_object_segicp, grid, options.observability, &crop);
  // The refined pose is scored only when the polish leaves it: the polish scores its own result.
  if (!PolishProbedDirections(grid, model, options, check) && refined.iterations > 0)
    check->segicp_score = ScoreAlignment(crop.points_model, refined.T_camera_object, grid, options.alignment).score;
}

/// For an object whose range the depth pushes back (OutlineFrame::range_biased), the estimate fitted
/// together with that push (validate/range_push.h), and the analysis taken again there.
void FitRangePush(const PointGrid& grid, const CropSource& model, const Eigen::Vector3d& tof_center_camera,
                  const ValidateOptions& options, LabelCheck* check) {
  const ModelCrop crop = model.Crop(check->T_camera_object_segicp);
  const RangePushFit fit = FitWithRangePush(crop, check->T_camera_object_segicp, grid, tof_center_camera,
                                            options.range_push, options.observability);
  // No push found (a box's flat faces each keep one incidence): the rigid fit stands.
  if (fit.iterations == 0 || !(fit.push_m > 0)) return;
  check->T_camera_object_segicp = fit.T_camera_object;
  check->range_push_mm = 1e3 * fit.push_m;
  // The score stays the rigid fit's: at the push's pose the deformed cloud lies behind the model by design.
  check->observability = AnalyseObservability(model, check->T_camera_object_segicp, grid, options.observability, &crop);
}

/// Label score, errors, success and verdict once an estimate (or none) is known; `made` as RefineEstimate.
void Finish(const PointGrid& grid, const Rigid3d& label, const CropSource& model, const CropSource& label_model,
            const ValidateOptions& options, const OutlineFrame* outline, LabelCheck* check,
            const TrackStep* made = nullptr) {
  check->label_score = ScoreAlignment(label_model.CropPoints(label).points_model, label, grid, options.alignment).score;
  if (check->estimated) {
    RefineEstimate(grid, model, options, made, check);
    if (outline && outline->range_biased) FitRangePush(grid, model, outline->tof_center_camera, options, check);
    // The directions no normal constrains take the outline's estimate and judgement (validate/outline.h).
    // The score stays the fit's: it is taken against the cloud the label's mask cut, which an outline
    // beyond the label's lies partly outside.
    // A range-biased object's estimate is moved across the ray by the outline only where it stayed the
    // rigid fit's (no push found).
    if (outline)
      check->outline = EstimateAlongOutline(*outline, options.outline, options.observability, &check->T_camera_object_segicp,
                                            &check->observability, outline->range_biased && !(check->range_push_mm > 0));
    ScoreEstimate(label, options, check);
  }
  DecideVerdict(options.verdict, check);
}

}  // namespace

LabelCheck BadInputCheck(VerdictReason code, std::string reason, int scene_points) {
  LabelCheck check;
  check.verdict = Verdict::kSuspect;
  check.reason_code = code;
  check.reason = std::move(reason);
  check.scene_points = scene_points;
  return check;
}

std::string_view ToString(Verdict verdict) {
  switch (verdict) {
    case Verdict::kAccept: return "accept";
    case Verdict::kSuspect: return "suspect";
    case Verdict::kReject: return "reject";
  }
  return "unknown";
}

std::string_view ToString(VerdictReason reason) {
  switch (reason) {
    case VerdictReason::kAgrees: return "agrees";
    case VerdictReason::kAgreesWhereObservable: return "agrees_where_observable";
    case VerdictReason::kDiffers: return "differs";
    case VerdictReason::kDisagrees: return "disagrees";
    case VerdictReason::kNoReliableEstimate: return "no_reliable_estimate";
    case VerdictReason::kLabelDoesNotFit: return "label_does_not_fit";
    case VerdictReason::kNoDepth: return "no_depth";
    case VerdictReason::kMaskSizeMismatch: return "mask_size_mismatch";
    case VerdictReason::kEmptyMask: return "empty_mask";
    case VerdictReason::kTooFewPoints: return "too_few_points";
    case VerdictReason::kUnreadableInput: return "unreadable_input";
    case VerdictReason::kCameraMountOff: return "camera_mount_off";
    case VerdictReason::kObjectMountOff: return "object_mount_off";
  }
  return "unknown";
}

bool IsBadInput(VerdictReason reason) {
  switch (reason) {
    case VerdictReason::kNoDepth:
    case VerdictReason::kMaskSizeMismatch:
    case VerdictReason::kEmptyMask:
    case VerdictReason::kTooFewPoints:
    case VerdictReason::kUnreadableInput: return true;
    default: return false;
  }
}

PoseErrors ComputePoseErrors(const Rigid3d& estimate, const Rigid3d& reference) {
  return {1e3 * TranslationDistanceM(estimate, reference), RotationAxisDistanceDeg(estimate, reference),
          RotationDistanceDeg(estimate, reference)};
}

ObservedDifference JudgedDifference(const LabelCheck& c) {
  if (c.judged_where_observable()) return c.observed;
  return {c.errors.position_mm, c.errors.rotation_angle_deg};
}

namespace {

/// The record's accept bounds from its estimate's precision (VerdictOptions): a precise estimate is
/// held to the floor, the label's own error; an imprecise one gets up to the widest bounds.
void SetAcceptBounds(const VerdictOptions& o, LabelCheck* c) {
  c->accept_position_mm = 1e3 * o.accept_position_m;
  c->accept_rotation_deg = o.accept_rotation_deg;
  if (!c->observability.analysed) return;
  const Eigen::Vector3d at = c->judged_where_observable() ? c->observability.center_object : Eigen::Vector3d::Zero();
  c->precision = PrecisionOf(c->observability, at, o.points_per_residual);
  const auto bound = [&](double floor, double resolution, double sigma, double widest) {
    return std::min(widest, std::hypot(floor, resolution, o.accept_sigmas * sigma));
  };
  c->accept_position_mm = bound(1e3 * o.accept_floor_position_m, c->resolution_position_mm, c->precision.position_mm,
                                1e3 * o.accept_position_m);
  c->accept_rotation_deg = bound(o.accept_floor_rotation_deg, c->resolution_rotation_deg, c->precision.rotation_deg,
                                 o.accept_rotation_deg);
}

}  // namespace

void DecideVerdict(const VerdictOptions& o, LabelCheck* c) {
  const std::string label_score = Str("label score ", Fixed(c->label_score, 2));
  if (c->estimated && c->observability.supported_points < o.min_supported_points) {
    c->verdict = Verdict::kSuspect;
    c->reason_code = VerdictReason::kTooFewPoints;
    c->reason = Str("too few points: the estimate rests on ", c->observability.supported_points,
                    " depth points of the object (< ", o.min_supported_points, "), the label is not checked (", label_score, ")");
    return;
  }
  if (!c->segicp_reliable) {
    const bool misfit = c->label_score < o.reject_label_score;
    c->verdict = misfit ? Verdict::kReject : Verdict::kSuspect;
    c->reason_code = misfit ? VerdictReason::kLabelDoesNotFit : VerdictReason::kNoReliableEstimate;
    c->reason = Str(misfit ? "label does not fit the depth" : "no reliable SegICP estimate", " (best score ",
                    Fixed(c->segicp_score, 2), ", ", label_score, ")");
    return;
  }
  // With unobservable directions only the observable part of the difference is evidence.
  const bool partly = c->judged_where_observable();
  const ObservedDifference judged = JudgedDifference(*c);
  const double position_mm = judged.position_mm;
  const double position_m = position_mm * 1e-3, angle = judged.rotation_deg;
  std::string differs = Str("SegICP differs by ", Fixed(position_mm, 1), " mm, ", Fixed(angle, 1), " deg",
                            partly ? Str(" in the ", c->observability.observable, " observable directions") : "",
                            " (score ", Fixed(c->segicp_score, 2), ", ", label_score, ")");
  if (partly) {
    differs += "; unobservable:";
    for (const std::string& u : c->observability.unobservable) differs += " " + u + ";";
    differs.pop_back();
  }
  SetAcceptBounds(o, c);
  differs += Str("; accept bounds ", Fixed(c->accept_position_mm, 1), " mm, ", Fixed(c->accept_rotation_deg, 1), " deg");
  if (position_mm <= c->accept_position_mm && angle <= c->accept_rotation_deg) {
    c->verdict = Verdict::kAccept;
    c->reason_code = partly ? VerdictReason::kAgreesWhereObservable : VerdictReason::kAgrees;
  } else if (position_m > o.reject_position_m || angle > o.reject_rotation_deg) {
    c->verdict = Verdict::kReject;
    c->reason_code = VerdictReason::kDisagrees;
  } else {
    c->verdict = Verdict::kSuspect;
    c->reason_code = VerdictReason::kDiffers;
  }
  c->reason = differs;
}

std::optional<SymmetryAxis> ChooseValidatorSymmetry(const std::vector<SymmetryAxis>& symmetries) {
  for (const SymmetryAxis& s : symmetries)
    if (s.step_deg == 0) return s;
  if (symmetries.empty()) return std::nullopt;
  return symmetries.front();
}

Rigid3d NearestSymmetricPose(const Rigid3d& T_camera_object, const Rigid3d& T_camera_object_reference,
                             const SymmetryAxis& symmetry) {
  const Eigen::Vector3d a = symmetry.axis_object.normalized();
  // trace(M Rot(a, t)) = A cos t + B sin t + a'Ma (Rodrigues), largest at t = atan2(B, A): the rotation
  // nearest to the reference.
  const Eigen::Matrix3d M = T_camera_object_reference.rotation().toRotationMatrix().transpose() *
                            T_camera_object.rotation().toRotationMatrix();
  Eigen::Matrix3d a_cross;
  a_cross << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  const double A = M.trace() - a.dot(M * a), B = (M * a_cross).trace();
  // A cos t + B sin t = sqrt(A^2 + B^2) cos(t - t*): for a discrete symmetry the best allowed angle is
  // the multiple of the step nearest to t*.
  double angle = std::atan2(B, A);
  if (symmetry.step_deg > 0) {
    const double step = RadFromDeg(symmetry.step_deg);
    angle = step * std::round(angle / step);
  }
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, a).toRotationMatrix();
  // The rotation about the axis through point_object, in the object frame.
  const Rigid3d about_axis(R, symmetry.point_object - R * symmetry.point_object);
  return T_camera_object * about_axis;
}

void ApplySymmetry(const Rigid3d& T_camera_object_label, const SymmetryAxis& symmetry, const ValidateOptions& options,
                   LabelCheck* check) {
  if (!check->estimated) return;
  const Rigid3d before = check->T_camera_object_segicp;
  check->T_camera_object_segicp = NearestSymmetricPose(before, T_camera_object_label, symmetry);
  // The same physical analysis in the turned object frame: coordinates change by S^-1.
  const Rigid3d S_inv = check->T_camera_object_segicp.inverse() * before;
  Observability& ob = check->observability;
  ob.center_object = S_inv * ob.center_object;
  const Eigen::Matrix3d R = S_inv.rotation_matrix();
  for (int k = 0; k < 6; ++k) {
    ob.directions.col(k).head<3>() = R * ob.directions.col(k).head<3>().eval();
    ob.directions.col(k).tail<3>() = R * ob.directions.col(k).tail<3>().eval();
  }
  if (ob.analysed) SummariseObservability(&ob);  // the sentences name directions in the turned frame
  ScoreEstimate(T_camera_object_label, options, check);
  DecideVerdict(options.verdict, check);
}

void LeaveOutRange(const Rigid3d& T_camera_object_label, const Eigen::Vector3d& tof_center_camera,
                   const ValidateOptions& options, LabelCheck* check) {
  Observability& ob = check->observability;
  if (!check->estimated || !ob.analysed) return;
  const Rigid3d& T = check->T_camera_object_segicp;
  Eigen::Matrix<double, 6, 1> along_ray;
  along_ray << Eigen::Vector3d::Zero(), T.rotation().inverse() * (T * ob.center_object - tof_center_camera).normalized();
  LeaveOutDirection(&ob, along_ray);
  ScoreEstimate(T_camera_object_label, options, check);
  DecideVerdict(options.verdict, check);
  check->reason += "; range along the time-of-flight camera's ray not judged (tof_range_biased)";
}

void ApplyDepthResolution(const DepthResolution& resolution, const ValidateOptions& options, LabelCheck* check) {
  if (!check->estimated || !check->observability.analysed) return;
  const double half_pixel_m = 0.5 * resolution.pixel_m;
  check->resolution_position_mm = 1e3 * std::hypot(half_pixel_m, 0.5 * resolution.step_m);
  check->resolution_rotation_deg = DegFromRad(std::atan2(half_pixel_m, check->observability.radius_m));
  DecideVerdict(options.verdict, check);
}

LabelCheck CheckLabel(const PointCloud& scene_camera, const Rigid3d& T_camera_object_label, const CropSource& model,
                      const std::vector<ModelCrop>& view_crops, const ValidateOptions& options,
                      const CropSource* label_model, const OutlineFrame* outline) {
  const PointCloud scene = VoxelDownsample(scene_camera, options.scene_voxel_m);
  if (static_cast<int>(scene.size()) < options.min_scene_points)
    return BadInputCheck(VerdictReason::kTooFewPoints,
                    Str("too few scene points (", scene.size(), " < ", options.min_scene_points, ")"),
                    static_cast<int>(scene.size()));
  const PointGrid grid(scene);
  const PointsOnlyCropSource hypotheses(model);  // the acquisition uses no normals
  const AcquisitionResult r =
      options.check_seed == AcquisitionSeed::kLabel
          ? AcquireAround(scene, grid, hypotheses, T_camera_object_label, options.acquisition, options.alignment)
          : Acquire(scene, grid, hypotheses, view_crops, options.acquisition, options.alignment);
  LabelCheck check;
  check.scene_points = static_cast<int>(scene.size());
  if (r.best >= 0) {
    check.estimated = true;
    check.T_camera_object_segicp = r.T_camera_model;
    check.segicp_score = r.score;
    check.icp = r.refine;
  }
  Finish(grid, T_camera_object_label, model, label_model ? *label_model : model, options, outline, &check);
  return check;
}

LabelCheck CheckLabelWithTrack(const PointCloud& scene_camera, const Rigid3d& T_camera_object_label,
                               const CropSource& model, const TrackStep& track, const ValidateOptions& options,
                               const CropSource* label_model, const OutlineFrame* outline) {
  const PointCloud scene = VoxelDownsample(scene_camera, options.scene_voxel_m);
  if (static_cast<int>(scene.size()) < options.min_scene_points)
    return BadInputCheck(VerdictReason::kTooFewPoints,
                    Str("too few scene points (", scene.size(), " < ", options.min_scene_points, ")"),
                    static_cast<int>(scene.size()));
  // The step's index holds the cloud given to it, which is this one when thinning left it as it was,
  // less (for a tracking step) the points beyond box_margin_m of the model's box at the prediction. The
  // estimate's queries (gates of a centimetre about a pose near the track) never reach those; only a label
  // more than box_margin_m - tau off the track could have matched some, in a score that is low anyway.
  const bool same_scene = track.scene_grid && scene.size() == scene_camera.size();
  const std::optional<PointGrid> own = same_scene ? std::nullopt : std::make_optional<PointGrid>(scene);
  const PointGrid& grid = same_scene ? *track.scene_grid : *own;
  LabelCheck check;
  check.scene_points = static_cast<int>(scene.size());
  if (track.measured) {
    check.estimated = true;
    check.T_camera_object_segicp = track.T_camera_object_measured;
    check.segicp_score = track.score;
    check.icp = track.icp;
  }
  Finish(grid, T_camera_object_label, model, label_model ? *label_model : model, options, outline, &check,
         same_scene && track.measured && track.refinement ? &track : nullptr);
  return check;
}

std::optional<LabelCheck> CheckFrameInput(const DepthImage& depth_m, const PinholeCamera& camera,
                                          const LabelImage& mask, uint16_t label_id) {
  if (depth_m.empty()) return BadInputCheck(VerdictReason::kNoDepth, "frame has no depth image");
  if (mask.width != depth_m.width || mask.height != depth_m.height)
    return BadInputCheck(VerdictReason::kMaskSizeMismatch, Str("mask is ", mask.width, "x", mask.height, ", depth is ",
                                                               depth_m.width, "x", depth_m.height));
  if (camera.width != depth_m.width || camera.height != depth_m.height)
    return BadInputCheck(VerdictReason::kMaskSizeMismatch, Str("camera is ", camera.width, "x", camera.height,
                                                               ", depth is ", depth_m.width, "x", depth_m.height));
  if (label_id == 0 || std::find(mask.data.begin(), mask.data.end(), label_id) == mask.data.end())
    return BadInputCheck(VerdictReason::kEmptyMask, Str("mask has no pixel of label ", label_id));
  return std::nullopt;
}

LabelCheck CheckLabelInFrame(const DepthImage& depth_m, const PinholeCamera& camera, const LabelImage& mask,
                             uint16_t label_id, const Rigid3d& T_camera_object_label, const CropSource& model,
                             const std::vector<ModelCrop>& view_crops, const ValidateOptions& options,
                             const MaskAtLabel* mask_at_label) {
  if (auto bad = CheckFrameInput(depth_m, camera, mask, label_id)) return *bad;
  const ObjectInFrame object(depth_m, camera, mask, label_id, T_camera_object_label, model, options);
  const std::optional<OutlineFrame> outline = mask_at_label ? std::optional(object.Outline(*mask_at_label)) : std::nullopt;
  LabelCheck check = CheckLabel(object.SceneCloud(), T_camera_object_label, object.crops(), view_crops, options,
                                object.label_crops(), outline ? &*outline : nullptr);
  check.occluder_pixels = object.occluder_pixels();
  return check;
}

ObjectInFrame::ObjectInFrame(const DepthImage& depth_m, const PinholeCamera& camera, const LabelImage& mask,
                             uint16_t label_id, const Rigid3d& T_camera_object_label, const CropSource& model,
                             const ValidateOptions& options)
    : depth_m_(depth_m),
      camera_(camera),
      label_mask_(mask),
      label_id_(label_id),
      occluder_margin_m_(options.occluder_margin_m),
      model_(model),
      filter_crops_(options.occluder_margin_m > 0),
      cut_(CutOccludersAtLabel(depth_m, camera, mask, label_id, T_camera_object_label, model, options)),
      mask_(cut_ ? cut_->mask : mask),
      visible_(model, camera, depth_m, mask_, label_id, options.occluder_margin_m),
      as_masked_(model, camera, depth_m, mask, label_id, options.occluder_margin_m) {}

PointCloud ObjectInFrame::SceneCloud() const { return DepthToPointsMasked(depth_m_, camera_, mask_, label_id_); }

OutlineFrame ObjectInFrame::Outline(const MaskAtLabel& drawn) const {
  return {&depth_m_, &camera_, &mask_, &label_mask_, label_id_, drawn.T_camera_object, &model_, occluder_margin_m_,
          drawn.range_biased, drawn.tof_center_camera};
}

std::optional<OccluderCut> CutOccludersAtLabel(const DepthImage& depth_m, const PinholeCamera& camera,
                                               const LabelImage& mask, uint16_t label_id,
                                               const Rigid3d& T_camera_object_label, const CropSource& model,
                                               const ValidateOptions& options) {
  if (options.occluder_margin_m <= 0) return std::nullopt;
  return CutOccluders(depth_m, camera, mask, label_id, model.CropPoints(T_camera_object_label), options.crop.pixel_m,
                      options.occluder_margin_m);
}

}  // namespace mocap
