#pragma once
// The model-to-scene alignment metric of the paper (section "Multi-Hypothesis Object Pose Estimation",
// "The Acquisition Phase"):
//
//     a(M_i, S) = |c| / |M_i|
//
// where c is the set of points of the model crop M_i with a *unique* corresponding point of the
// segmented scene cloud S at most tau metres away. "Each point in M_i is mapped to the closest point
// in S within tau that has not been already mapped to another point in M_i, and then is added to c."
// Model points are visited in their stored order; a scene point is claimed at most once.
#include "core/rigid3.h"
#include "validate/point_grid.h"
#include "validate/point_cloud.h"

namespace mocap {

struct AlignmentOptions {
  double tau_m = 0.01;  ///< the paper's tau = 1 cm
  /// Throws InputError when tau_m is not positive.
  void check() const;
};

struct AlignmentScore {
  double score = 0.0;     ///< a(M, S) in [0, 1]; 0 for an empty crop
  int matched = 0;        ///< |c|
  int model_points = 0;   ///< |M|
  int second_choice = 0;  ///< matches that fell back past a claimed nearest point (diagnostic)
};

/// Scores the crop `crop_model` (model frame) placed at `T_scene_model` against the scene grid.
AlignmentScore ScoreAlignment(const PointCloud& crop_model, const Rigid3d& T_scene_model, const PointGrid& scene,
                              const AlignmentOptions& options);

}  // namespace mocap
