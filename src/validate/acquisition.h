#pragma once
// The acquisition phase of the paper ("The Acquisition Phase"): N model crops, each initialised at the
// median of the object's scene cloud, registered by point-to-point ICP in parallel, each scored by the
// alignment metric a(M, S); the best score above epsilon starts tracking. Registered coarse-to-fine
// (docs/validation.md "Acquisition"): all N on a subset of their crop points, ranked by the subset's
// score; the best refine_count refined on their full crops and scored by the full a(M, S).
#include <memory>
#include <string>
#include <vector>

#include "validate/alignment_score.h"
#include "validate/icp.h"
#include "validate/point_grid.h"
#include "validate/model_crop.h"
#include "validate/registration.h"

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
  /// Coarse stage: each hypothesis is registered and ranked on every `hypothesis_stride`-th crop point
  /// (about 150 of a 1,200-point crop). The ranking score is a(M, S) of that subset: an estimate of
  /// the paper's score at an eighth of the cost; the reported score is the full one (fine stage).
  int hypothesis_stride = 8;
  /// ICP per hypothesis on that subset: "a few iterations" (the paper), gate 5 cm shrinking to 1 cm
  /// by the 6th iteration; only the hypotheses that survive need to converge.
  IcpOptions icp = [] {
    IcpOptions o;
    o.initial_correspondence_distance_m = 0.05;
    o.max_iterations = 8;
    return o;
  }();
  /// Coarse-stage scores within this of the best count as tied; ties go to the lowest inlier RMSE.
  /// a(M, S) saturates at 1 when a crop slides within a larger planar face, so it cannot rank those
  /// alone. The same rule picks the winner of the fine stage.
  double score_tie = 0.02;
  /// Fine stage: this many of the best-ranked hypotheses are refined (in parallel: 2 fills two
  /// cores) and the best refined one wins. 1 trusts the coarse ranking alone.
  int refine_count = 2;
  /// Seeded at a prior (AcquireAround): refined hypotheses tied in score and with an inlier RMSE within
  /// this fraction of the winner's are told apart by nearness to the prior (the depth cannot).
  double prior_rmse_tie = 0.05;
  /// The refinement ("a few iterations of the tracking phase" in the paper): the crop is recomputed as
  /// seen from the hypothesis's pose (a crop from a neighbouring view lacks part of the visible
  /// surface and can settle a few millimetres off) and registered, every 3rd point until converged,
  /// then all of them, with Besl & McKay's acceleration against the slow slide along planar faces.
  IcpOptions refine_icp = [] {
    IcpOptions o;
    o.initial_correspondence_distance_m = 0.01;
    o.max_iterations = 100;
    o.source_stride = 3;
    o.translation_epsilon_m = 2e-5;
    o.rotation_epsilon_deg = 0.005;
    o.accelerate = true;
    return o;
  }();
  /// The registration of both stages, and of the tracker's tracking step (validate/registration.h); null:
  /// the validator's own. Here rather than beside the tracking options because every acquisition, in a
  /// tracker or in a label check, is handed these options.
  std::shared_ptr<const Registration> registration;
  void check() const;
};

struct Hypothesis {
  Rigid3d T_camera_model_init;
  IcpResult icp;         ///< the coarse-stage ICP (on the crop subset)
  AlignmentScore score;  ///< a(M, S) of the crop subset at icp's pose (the coarse ranking)
  int crop_index = 0;
};

struct AcquisitionResult {
  bool acquired = false;        ///< best score >= epsilon
  Rigid3d T_camera_model;       ///< best hypothesis (meaningful when hypotheses is non-empty)
  double score = 0.0;           ///< a(M, S) of the winner after refinement (all crop points)
  IcpResult refine;             ///< the refinement of the winner
  ModelCrop refined_crop;       ///< the crop visible from the refined pose
  int best = -1;                ///< index into hypotheses: the one whose refinement won
  std::vector<Hypothesis> hypotheses;
  std::vector<ModelCrop> crops;  ///< the crop of each hypothesis (crop_index refers here)
  std::string reason;           ///< why nothing was acquired (empty when acquired)
};

/// The paper's view-sphere crops (computed once per model; they do not depend on the frame).
std::vector<ModelCrop> MakeViewSphereCrops(const CropSource& model, const AcquisitionOptions& options);

/// Acquisition from the view-sphere crops: each crop is turned so that its virtual camera looks along
/// the ray to the scene median, then placed with its median on the scene median. `scene` is the
/// object's scene cloud (camera frame) that `scene_grid` indexes.
AcquisitionResult Acquire(const PointCloud& scene, const PointGrid& scene_grid, const CropSource& model,
                          const std::vector<ModelCrop>& crops, const AcquisitionOptions& options,
                          const AlignmentOptions& alignment);

/// Acquisition with a prior pose (a label, a filter prediction): num_crops hypotheses, the prior's
/// rotation and rotations up to prior_spread_deg about it, each with the crop visible from the camera
/// at that pose, placed at the scene median as above; and one more, the prior itself where it is.
AcquisitionResult AcquireAround(const PointCloud& scene, const PointGrid& scene_grid, const CropSource& model,
                                const Rigid3d& T_camera_model_prior, const AcquisitionOptions& options,
                                const AlignmentOptions& alignment);

}  // namespace mocap
