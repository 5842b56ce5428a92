#pragma once
// One object's SegICP state machine over a sequence of frames: acquisition until a hypothesis scores
// above epsilon, then tracking (box pruning, ICP from the filter's prediction, Kalman update weighted
// by the score); a score below theta propagates the filter and returns to acquisition.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "validate/observability.h"
#include "validate/point_grid.h"
#include "validate/pose_filter.h"
#include "validate/validate_options.h"

namespace mocap {

enum class TrackMode { kAcquisition, kTracking };
std::string_view ToString(TrackMode mode);

struct TrackStep {
  TrackMode mode = TrackMode::kAcquisition;  ///< the phase run in this frame
  bool has_pose = false;                     ///< the filter holds a pose (not lost)
  Rigid3d T_camera_object;                   ///< filtered pose in this frame's camera
  bool measured = false;                     ///< ICP produced a pose this frame
  Rigid3d T_camera_object_measured;
  double score = 0.0;                        ///< a(M, S) of the measurement
  bool measurement_accepted = false;         ///< fused into the filter (score and gate passed)
  int scene_points = 0;                      ///< after thinning (and pruning, when tracking)
  IcpResult icp;
  std::string note;                          ///< what happened, for reports
  /// The index the step measured against, when Step did not thin the cloud it was given: the whole
  /// cloud for an acquisition, the points near the predicted pose for a tracking step (box_margin_m
  /// around the model's box). A label check of the same cloud measures against it too.
  std::shared_ptr<const PointGrid> scene_grid;
  /// The tracking step's point-to-plane refinement when the validator's own registration made it
  /// against `scene_grid` and it converged: its result is the measurement and its last equations are the
  /// analysis there, made with `refinement_crop`. A label check takes it as its own first refinement
  /// (CheckLabelWithTrack) instead of repeating it.
  std::optional<PlaneRefinement> refinement;
  ModelCrop refinement_crop;
};

class ObjectTracker {
 public:
  /// `model` must outlive the tracker. Throws InputError when options.check() fails.
  ObjectTracker(const CropSource& model, const ValidateOptions& options);

  /// One frame: the object's scene cloud (camera frame, e.g. DepthToPointsMasked), the camera pose in
  /// the world from its tracker body, and the frame time. Stamps must increase.
  /// `T_camera_object_prior` (may be null), e.g. the frame's label, seeds the acquisitions (the first
  /// frame, after a loss, a cross-check); without it the filter's prediction seeds them while it holds a
  /// pose, else the paper's view sphere. `cross_check`: run an acquisition instead of a tracking step
  /// (a periodic check against a track settled on a wrong minimum; the session check asks for one at
  /// every frame whose index is a multiple of TrackingOptions::reacquire_every).
  /// A tracking step that fails (too few points near the prediction, a score below theta) is followed
  /// by an acquisition in the same frame when a prior is given. `frame_model` (may be null) replaces
  /// the tracker's crop source for this frame (crops as the frame sees them, VisibleInFrameCropSource).
  TrackStep Step(const PointCloud& scene_camera, const Rigid3d& T_world_camera, int64_t stamp_ns,
                 const Rigid3d* T_camera_object_prior = nullptr, const CropSource* frame_model = nullptr,
                 bool cross_check = false);

  TrackMode mode() const { return mode_; }
  const PoseFilter& filter() const { return filter_; }

 private:
  /// `scene_given`: `scene` is the cloud given to Step (thinning left it as it was).
  void RunAcquisition(const PointCloud& scene, bool scene_given, const Rigid3d& T_world_camera, int64_t stamp_ns,
                      const Rigid3d* T_camera_object_prior, const CropSource& model, TrackStep* step);
  void RunTracking(const PointCloud& scene, bool scene_given, const Rigid3d& T_world_camera, const CropSource& model,
                   TrackStep* step);

  const CropSource& model_;
  ValidateOptions options_;
  std::vector<ModelCrop> view_crops_;
  Box3d model_box_;
  PoseFilter filter_;
  TrackMode mode_ = TrackMode::kAcquisition;
  int64_t last_stamp_ns_ = 0;
};

}  // namespace mocap
