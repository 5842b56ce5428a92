#include "validate/tracker.h"

#include "core/check.h"

namespace mocap {

std::string_view ToString(TrackMode mode) {
  return mode == TrackMode::kTracking ? "tracking" : "acquisition";
}

ObjectTracker::ObjectTracker(const CropSource& model, const ValidateOptions& options)
    : model_(model), options_((options.check(), options)), filter_(options.filter) {
  model_box_ = BoundingBox(model_.surface_model(), options_.tracking.box_margin_m);
}

TrackStep ObjectTracker::Step(const PointCloud& scene_camera, const Rigid3d& T_world_camera, int64_t stamp_ns,
                              const Rigid3d* T_camera_object_prior, const CropSource* frame_model, bool cross_check) {
  const CropSource& model = frame_model ? *frame_model : model_;
  TrackStep step;
  if (filter_.initialized()) filter_.Predict(stamp_ns);
  if (filter_.lost()) {
    filter_ = PoseFilter(options_.filter);
    mode_ = TrackMode::kAcquisition;
    step.note = "track lost (pose uncertainty above the limit); ";
  }
  const PointCloud scene = VoxelDownsample(scene_camera, options_.scene_voxel_m);
  // Thinning keeps the order and leaves a point alone in its voxel as it is: a cloud of the same size is
  // the given one.
  const bool scene_given = scene.size() == scene_camera.size();
  step.mode = mode_;
  step.scene_points = static_cast<int>(scene.size());
  bool acquire = false;
  if (step.scene_points < options_.min_scene_points) {
    step.note += Str("too few scene points (", step.scene_points, "); propagating");
  } else if (mode_ == TrackMode::kTracking) {
    const bool gap = stamp_ns - last_stamp_ns_ > static_cast<int64_t>(options_.tracking.max_gap_s * 1e9);
    const Rigid3d predicted = T_world_camera.inverse() * filter_.pose();
    const bool prior_far = T_camera_object_prior &&
                           (TranslationDistanceM(predicted, *T_camera_object_prior) > options_.tracking.max_prior_distance_m ||
                            RotationDistanceDeg(predicted, *T_camera_object_prior) > options_.tracking.max_prior_angle_deg);
    if (cross_check || gap || prior_far) {
      step.note += gap ? "frames too far apart to track; " : prior_far ? "prior far from the track; " : "periodic cross-check; ";
      acquire = true;
    } else {
      RunTracking(scene, scene_given, T_world_camera, model, &step);
      // A failed step (back to acquisition) is followed by an acquisition now when a prior can seed it.
      acquire = mode_ == TrackMode::kAcquisition && T_camera_object_prior;
    }
  } else {
    acquire = true;
  }
  if (acquire) {
    TrackStep fresh;
    fresh.scene_points = static_cast<int>(scene.size());
    fresh.note = std::move(step.note);
    step = std::move(fresh);
    RunAcquisition(scene, scene_given, T_world_camera, stamp_ns, T_camera_object_prior, model, &step);
  }
  last_stamp_ns_ = stamp_ns;
  step.has_pose = filter_.initialized() && !filter_.lost();
  if (step.has_pose) step.T_camera_object = T_world_camera.inverse() * filter_.pose();
  return step;
}

void ObjectTracker::RunTracking(const PointCloud& scene, bool scene_given, const Rigid3d& T_world_camera,
                                const CropSource& model, TrackStep* step) {
  const Rigid3d T_camera_world = T_world_camera.inverse();
  const Rigid3d predicted = T_camera_world * filter_.pose();
  const PointCloud pruned = CropToBox(scene, predicted, model_box_);
  step->scene_points = static_cast<int>(pruned.size());
  if (step->scene_points < options_.min_scene_points) {
    mode_ = TrackMode::kAcquisition;
    step->note += Str("too few points near the predicted pose (", step->scene_points, "); back to acquisition");
    return;
  }
  const auto grid = std::make_shared<const PointGrid>(pruned);
  ModelCrop crop = model.Crop(predicted);
  // Point-to-plane from the prediction; the validator's own moves only in the directions the depth
  // constrains: a table top tracked by point-to-point ICP slid along its plane from frame to frame.
  PlaneRefinement refined;
  step->icp = RegistrationOrOwn(options_.acquisition.registration)
                  .PointToPlane(crop, *grid, predicted, options_.observability, options_.tracking.initial_gate_m, &refined);
  if (scene_given && refined.converged) step->refinement = std::move(refined);
  step->measured = true;
  step->T_camera_object_measured = step->icp.T_target_source;
  step->score = ScoreAlignment(crop.points_model, step->T_camera_object_measured, *grid, options_.alignment).score;
  if (scene_given) step->scene_grid = grid;
  if (step->refinement) step->refinement_crop = std::move(crop);
  if (step->score < options_.tracking.theta) {
    mode_ = TrackMode::kAcquisition;
    step->note += Str("score ", step->score, " below theta; propagating, back to acquisition");
    return;
  }
  const FilterUpdate update = filter_.Update(T_world_camera * step->T_camera_object_measured, step->score);
  step->measurement_accepted = update.accepted;
  if (!update.accepted) step->note += Str("measurement gated out (Mahalanobis^2 ", update.mahalanobis_sq, ")");
}

void ObjectTracker::RunAcquisition(const PointCloud& scene, bool scene_given, const Rigid3d& T_world_camera,
                                   int64_t stamp_ns, const Rigid3d* T_camera_object_prior, const CropSource& model,
                                   TrackStep* step) {
  const auto shared_grid = std::make_shared<const PointGrid>(scene);
  const PointGrid& grid = *shared_grid;
  if (scene_given) step->scene_grid = shared_grid;
  // A given prior seeds the hypotheses, else the filter's prediction while it holds a pose, else the
  // view sphere (whose crops are made on first use).
  AcquisitionResult r;
  const PointsOnlyCropSource hypotheses(model);  // the acquisition uses no normals
  if (T_camera_object_prior || filter_.initialized()) {
    const Rigid3d prior = T_camera_object_prior ? *T_camera_object_prior : T_world_camera.inverse() * filter_.pose();
    r = AcquireAround(scene, grid, hypotheses, prior, options_.acquisition, options_.alignment);
  } else {
    if (view_crops_.empty()) view_crops_ = MakeViewSphereCrops(PointsOnlyCropSource(model_), options_.acquisition);
    r = Acquire(scene, grid, hypotheses, view_crops_, options_.acquisition, options_.alignment);
  }
  if (r.best < 0) {
    step->note += r.reason;
    return;
  }
  step->measured = true;
  step->icp = r.refine;
  step->T_camera_object_measured = r.T_camera_model;
  step->score = r.score;
  if (!r.acquired) {
    step->note += r.reason;
    return;
  }
  const Rigid3d T_world_object = T_world_camera * r.T_camera_model;
  // A fresh acquisition (re-)anchors the filter: it replaces a track the measurements had left.
  filter_.Initialize(T_world_object, stamp_ns, r.score);
  step->measurement_accepted = true;
  mode_ = TrackMode::kTracking;
}

}  // namespace mocap
