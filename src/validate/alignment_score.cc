#include "validate/alignment_score.h"

#include <vector>

#include "core/check.h"

namespace mocap {

void AlignmentOptions::check() const {
  if (!(tau_m > 0)) throw InputError("AlignmentOptions", "tau_m must be positive");
}

AlignmentScore ScoreAlignment(const PointCloud& crop_model, const Rigid3d& T_scene_model, const PointGrid& scene,
                              const AlignmentOptions& options) {
  AlignmentScore out;
  out.model_points = static_cast<int>(crop_model.size());
  if (crop_model.empty() || scene.size() == 0) return out;
  const Eigen::Matrix3d R = T_scene_model.rotation_matrix();
  const Eigen::Vector3d t = T_scene_model.translation();
  const double tau_sq = options.tau_m * options.tau_m;
  std::vector<char> claimed(scene.size(), 0);
  size_t nearest = 0;
  double d2 = 0.0;
  for (const auto& p_model : crop_model) {
    const Eigen::Vector3d p = R * p_model + t;
    if (!scene.Nearest(p, options.tau_m, &nearest, &d2) || d2 > tau_sq) continue;
    if (!claimed[nearest]) {
      // The common case: the closest point is free. Equivalent to the paper's radius search, whose
      // sorted result starts with this point, at the cost of a single 1-NN query.
      claimed[nearest] = 1;
      ++out.matched;
      continue;
    }
    // The closest point is taken: the closest free one in the radius-tau neighbourhood.
    if (!scene.NearestUntaken(p, options.tau_m, claimed, tau_sq, &nearest)) continue;
    claimed[nearest] = 1;
    ++out.matched;
    ++out.second_choice;
  }
  out.score = static_cast<double>(out.matched) / static_cast<double>(out.model_points);
  return out;
}

}  // namespace mocap
