#pragma once
// One object's SegICP state machine over a sequence of frames: acquisition until a hypothesis scores
// above epsilon, then tracking (box pruning, ICP from the filter's prediction, Kalman update weighted
// by the score); a score below theta propagates the filter and returns to acquisition.
#include <cstdint>
#include <string>
#include <vector>

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
  void RunAcquisition(const PointCloud& scene, const Rigid3d& T_world_camera, int64_t stamp_ns,
                      const Rigid3d* T_camera_object_prior, const CropSource& model, TrackStep* step);
  void RunTracking(const PointCloud& scene, const Rigid3d& T_world_camera, const CropSource& model, TrackStep* step);

  const CropSource& model_;
  ValidateOptions options_;
  std::vector<ModelCrop> view_crops_;
  Box3d model_box_;
  PoseFilter filter_;
  TrackMode mode_ = TrackMode::kAcquisition;
  int64_t last_stamp_ns_ = 0;
};

}  // namespace mocap
