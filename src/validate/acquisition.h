#pragma once
// The acquisition phase of the paper ("The Acquisition Phase"): N model crops, each initialised at the
// median of the object's scene cloud, registered by point-to-point ICP in parallel, each scored by the
// alignment metric a(M, S); the best score above epsilon starts tracking.
#include <string>
#include <vector>

#include "validate/alignment_score.h"
#include "validate/icp.h"
#include "validate/kdtree.h"
#include "validate/model_crop.h"

namespace mocap {

struct AcquisitionOptions {
  int num_crops = 30;               ///< the paper's N = 30
  double epsilon = 0.75;            ///< the paper's switch-to-tracking threshold on a(M, S)
  /// View sphere of the crops (degrees above the model x-y plane). The paper names azimuth and
  /// elevation without a range; objects held in a tracked hand can show any side, so the default is
  /// the whole sphere.
  double min_elevation_deg = -90.0;
  double max_elevation_deg = 90.0;
  /// Distance of the virtual camera from the model origin when crops are computed, metres.
  double crop_distance_m = 1.0;
  /// Rotations of each crop about the viewing ray tried as separate hypotheses (1 = the paper: the
  /// crop's own image-up, model +z up). Raise when the camera roll relative to the object is unknown.
  int roll_steps = 1;
  /// Spread of the hypotheses about a prior orientation (AcquireAround), degrees.
  double prior_spread_deg = 20.0;
  /// ICP per hypothesis: "a few iterations" (the paper) on every 8th crop point; only the winner
  /// needs to converge, and it is refined below.
  IcpOptions icp = [] {
    IcpOptions o;
    o.initial_correspondence_distance_m = 0.05;
    o.max_iterations = 20;
    o.source_stride = 8;
    return o;
  }();
  /// Hypotheses scoring within this of the best score count as tied; the tie goes to the lowest inlier
  /// RMSE. a(M, S) saturates at 1 when a crop slides within a larger planar face, so it cannot rank
  /// those alone.
  double score_tie = 0.02;
  /// The winner is refined before it is reported ("a few iterations of the tracking phase" in the
  /// paper): the crop is recomputed as seen from the winning pose (a crop from a neighbouring view
  /// lacks part of the visible surface and can settle a few millimetres off) and registered on all its
  /// points.
  IcpOptions refine_icp = [] {
    IcpOptions o;
    o.initial_correspondence_distance_m = 0.01;
    o.max_iterations = 100;
    o.translation_epsilon_m = 2e-5;
    o.rotation_epsilon_deg = 0.005;
    return o;
  }();
  void check() const;
};

struct Hypothesis {
  Rigid3d T_camera_model_init;
  IcpResult icp;
  AlignmentScore score;
  int crop_index = 0;
};

struct AcquisitionResult {
  bool acquired = false;        ///< best score >= epsilon
  Rigid3d T_camera_model;       ///< best hypothesis (meaningful when hypotheses is non-empty)
  double score = 0.0;           ///< a(M, S) of the best hypothesis after refinement
  IcpResult refine;             ///< the refinement of the best hypothesis
  ModelCrop refined_crop;       ///< the crop visible from the refined pose
  int best = -1;                ///< index into hypotheses
  std::vector<Hypothesis> hypotheses;
  std::vector<ModelCrop> crops;  ///< the crop of each hypothesis (crop_index refers here)
  std::string reason;           ///< why nothing was acquired (empty when acquired)
};

/// The paper's view-sphere crops (computed once per model; they do not depend on the frame).
std::vector<ModelCrop> MakeViewSphereCrops(const CropSource& model, const AcquisitionOptions& options);

/// Acquisition from the view-sphere crops: each crop is turned so that its virtual camera looks along
/// the ray to the scene median, then placed with its median on the scene median. `scene` is the
/// object's scene cloud (camera frame) that `scene_tree` indexes.
AcquisitionResult Acquire(const PointCloud& scene, const KdTree& scene_tree, const CropSource& model,
                          const std::vector<ModelCrop>& crops, const AcquisitionOptions& options,
                          const AlignmentOptions& alignment);

/// Acquisition with an orientation prior (a label, a filter prediction): num_crops hypotheses, the
/// prior's rotation and rotations up to prior_spread_deg about it, each with the crop visible from
/// the camera at that pose, placed at the scene median as above.
AcquisitionResult AcquireAround(const PointCloud& scene, const KdTree& scene_tree, const CropSource& model,
                                const Rigid3d& T_camera_model_prior, const AcquisitionOptions& options,
                                const AlignmentOptions& alignment);

}  // namespace mocap
