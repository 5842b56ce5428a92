#include "validate/acquisition.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/check.h"

namespace mocap {
namespace {

/// The smallest rotation taking +z onto the unit vector `dir`.
Eigen::Matrix3d RotationZTo(const Eigen::Vector3d& dir) {
  return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), dir).toRotationMatrix();
}

/// Places a crop with rotation R so that its median lands on the scene median.
Rigid3d PlaceAtMedian(const Eigen::Matrix3d& R, const ModelCrop& crop, const Eigen::Vector3d& scene_median) {
  const Eigen::Vector3d crop_median = crop.points_model.empty() ? Eigen::Vector3d::Zero()
                                                                : ComponentMedian(crop.points_model);
  return Rigid3d(R, scene_median - R * crop_median);
}

/// ICP and score of every hypothesis, in parallel (the paper runs them "in parallel"), then the best.
void RunHypotheses(const KdTree& scene_tree, const CropSource& model, const AcquisitionOptions& options,
                   const AlignmentOptions& alignment, AcquisitionResult* result) {
  auto& hyps = result->hypotheses;
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < static_cast<int>(hyps.size()); ++i) {
    const PointCloud& crop = result->crops[hyps[i].crop_index].points_model;
    hyps[i].icp = AlignPointToPoint(crop, scene_tree, hyps[i].T_camera_model_init, options.icp);
    hyps[i].score = ScoreAlignment(crop, hyps[i].icp.T_target_source, scene_tree, alignment);
  }
  double top = -1.0;
  for (const auto& h : hyps) top = std::max(top, h.score.score);
  for (int i = 0; i < static_cast<int>(hyps.size()); ++i) {
    if (hyps[i].score.score < top - options.score_tie) continue;
    if (result->best < 0 || hyps[i].icp.inlier_rmse_m < hyps[result->best].icp.inlier_rmse_m) result->best = i;
  }
  if (result->best < 0) {
    result->reason = "no hypotheses";
    return;
  }
  result->refined_crop = model.Crop(hyps[result->best].icp.T_target_source);
  result->refine = AlignPointToPoint(result->refined_crop.points_model, scene_tree,
                                     hyps[result->best].icp.T_target_source, options.refine_icp);
  result->T_camera_model = result->refine.T_target_source;
  result->score = ScoreAlignment(result->refined_crop.points_model, result->T_camera_model, scene_tree, alignment).score;
  result->acquired = result->score >= options.epsilon;
  if (!result->acquired)
    result->reason = Str("best alignment score ", result->score, " below epsilon ", options.epsilon);
}

}  // namespace

void AcquisitionOptions::check() const {
  if (num_crops < 1) throw InputError("AcquisitionOptions", "num_crops must be >= 1");
  if (!(epsilon > 0 && epsilon <= 1)) throw InputError("AcquisitionOptions", "epsilon must lie in (0, 1]");
  if (!(min_elevation_deg >= -90 && min_elevation_deg <= max_elevation_deg && max_elevation_deg <= 90))
    throw InputError("AcquisitionOptions", "need -90 <= min_elevation_deg <= max_elevation_deg <= 90");
  if (!(crop_distance_m > 0)) throw InputError("AcquisitionOptions", "crop_distance_m must be positive");
  if (roll_steps < 1) throw InputError("AcquisitionOptions", "roll_steps must be >= 1");
  if (!(prior_spread_deg >= 0 && prior_spread_deg <= 180))
    throw InputError("AcquisitionOptions", "prior_spread_deg must lie in [0, 180]");
  if (!(score_tie >= 0 && score_tie < 1)) throw InputError("AcquisitionOptions", "score_tie must lie in [0, 1)");
  icp.check();
  refine_icp.check();
}

std::vector<ModelCrop> MakeViewSphereCrops(const CropSource& model, const AcquisitionOptions& options) {
  const Eigen::Vector3d center = Centroid(model.surface_model());
  const std::vector<Rigid3d> views = ViewSpherePoses(options.num_crops, options.min_elevation_deg,
                                                     options.max_elevation_deg, center, options.crop_distance_m);
  std::vector<ModelCrop> crops(views.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < static_cast<int>(views.size()); ++i) crops[i] = model.Crop(views[i]);
  return crops;
}

AcquisitionResult Acquire(const PointCloud& scene, const KdTree& scene_tree, const CropSource& model,
                          const std::vector<ModelCrop>& crops, const AcquisitionOptions& options,
                          const AlignmentOptions& alignment) {
  AcquisitionResult result;
  if (scene.empty()) {
    result.reason = "empty scene cloud";
    return result;
  }
  const Eigen::Vector3d median = ComponentMedian(scene);
  const Eigen::Matrix3d R_ray = RotationZTo(median.normalized());
  result.crops = crops;
  for (int c = 0; c < static_cast<int>(crops.size()); ++c) {
    if (crops[c].points_model.empty()) continue;
    for (int k = 0; k < options.roll_steps; ++k) {
      const double roll = 2.0 * std::numbers::pi * k / options.roll_steps;
      const Eigen::Matrix3d R = R_ray * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                                crops[c].T_camera_model.rotation_matrix();
      result.hypotheses.push_back({PlaceAtMedian(R, crops[c], median), {}, {}, c});
    }
  }
  RunHypotheses(scene_tree, model, options, alignment, &result);
  return result;
}

AcquisitionResult AcquireAround(const PointCloud& scene, const KdTree& scene_tree, const CropSource& model,
                                const Rigid3d& T_camera_model_prior, const AcquisitionOptions& options,
                                const AlignmentOptions& alignment) {
  AcquisitionResult result;
  if (scene.empty()) {
    result.reason = "empty scene cloud";
    return result;
  }
  const Eigen::Vector3d median = ComponentMedian(scene);
  // The prior itself, then rotation offsets on a Fibonacci sphere of axes with angles growing to the spread.
  const int n = options.num_crops;
  std::vector<Rigid3d> starts(n);
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z);
    const Eigen::Vector3d axis(r * std::cos(golden * i), r * std::sin(golden * i), z);
    const double angle = i == 0 ? 0.0 : RadFromDeg(options.prior_spread_deg) * std::sqrt(static_cast<double>(i) / (n - 1));
    starts[i] = Rigid3d(T_camera_model_prior.rotation() * Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis)),
                        T_camera_model_prior.translation());
  }
  result.crops.resize(n);
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < n; ++i) result.crops[i] = model.Crop(starts[i]);
  for (int i = 0; i < n; ++i)
    if (!result.crops[i].points_model.empty())
      result.hypotheses.push_back({PlaceAtMedian(starts[i].rotation_matrix(), result.crops[i], median), {}, {}, i});
  RunHypotheses(scene_tree, model, options, alignment, &result);
  return result;
}

}  // namespace mocap
