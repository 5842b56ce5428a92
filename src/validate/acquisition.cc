#include "validate/acquisition.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

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

/// Every `stride`-th point, in order; the stride is lowered to keep at least 50 points where the cloud
/// has them (the rule of IcpOptions::source_stride), so that small crops are not thinned to nothing.
PointCloud EveryNth(const PointCloud& points, int stride) {
  stride = std::min(stride, std::max(1, static_cast<int>(points.size()) / 50));
  PointCloud out;
  out.reserve(points.size() / static_cast<size_t>(stride) + 1);
  for (size_t i = 0; i < points.size(); i += static_cast<size_t>(stride)) out.push_back(points[i]);
  return out;
}

/// True when (score_a, rmse_a) ranks before (score_b, rmse_b) among candidates within `tie` of the
/// top score `top`: a(M, S) saturates at 1 when a crop slides within a larger planar face, so tied
/// scores are ranked by the inlier RMSE.
bool RanksBefore(double score_a, double rmse_a, double score_b, double rmse_b, double top, double tie) {
  const bool tied_a = score_a >= top - tie, tied_b = score_b >= top - tie;
  if (tied_a != tied_b) return tied_a;
  if (tied_a) return rmse_a < rmse_b;
  return score_a > score_b;
}

/// Coarse stage: every hypothesis registered on every hypothesis_stride-th crop point and scored on the
/// same points, in parallel (the paper runs the hypotheses "in parallel"). Returns the hypotheses'
/// indices, best first.
std::vector<int> RegisterCoarse(const PointGrid& scene_grid, const AcquisitionOptions& options,
                                const AlignmentOptions& alignment, AcquisitionResult* result) {
  auto& hyps = result->hypotheses;
  const Registration& registration = RegistrationOrOwn(options.registration);
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < static_cast<int>(hyps.size()); ++i) {
    const PointCloud crop = EveryNth(result->crops[hyps[i].crop_index].points_model, options.hypothesis_stride);
    hyps[i].icp = registration.PointToPoint(crop, scene_grid, hyps[i].T_camera_model_init, options.icp);
    hyps[i].score = ScoreAlignment(crop, hyps[i].icp.T_target_source, scene_grid, alignment);
  }
  double top = -1.0;
  for (const auto& h : hyps) top = std::max(top, h.score.score);
  std::vector<int> order(hyps.size());
  for (int i = 0; i < static_cast<int>(order.size()); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return RanksBefore(hyps[a].score.score, hyps[a].icp.inlier_rmse_m, hyps[b].score.score, hyps[b].icp.inlier_rmse_m,
                       top, options.score_tie);
  });
  return order;
}

/// A hypothesis carried to the fine stage: re-cropped at its pose, refined on all crop points, scored.
struct Refined {
  ModelCrop crop;
  IcpResult icp;
  double score = 0.0;
};

/// Fine stage: the best refine_count hypotheses refined in parallel; the winner is the best refined
/// one by the full a(M, S) (ties by inlier RMSE), so a hypothesis that the subsample ranked second can
/// still win.
void RefineBest(const PointGrid& scene_grid, const CropSource& model, const AcquisitionOptions& options,
                const AlignmentOptions& alignment, std::vector<int> order, const Rigid3d* prior, AcquisitionResult* result) {
  const int count = std::min<int>(options.refine_count, static_cast<int>(order.size()));
  // Seeded at a prior (the last hypothesis is the prior where it is): where its coarse score ties with
  // the best, it is refined too, in the last slot, so that a tie can be settled by nearness below.
  if (prior && count > 1) {
    const int seed = static_cast<int>(result->hypotheses.size()) - 1;
    const auto at = std::find(order.begin(), order.end(), seed);
    const double top_coarse = result->hypotheses[order[0]].score.score;
    if (at - order.begin() >= count && result->hypotheses[seed].score.score >= top_coarse - options.score_tie)
      std::rotate(order.begin() + count - 1, at, at + 1);
  }
  std::vector<Refined> refined(count);
  const Registration& registration = RegistrationOrOwn(options.registration);
#pragma omp parallel for schedule(dynamic, 1)
  for (int j = 0; j < count; ++j) {
    const Rigid3d& T_coarse = result->hypotheses[order[j]].icp.T_target_source;
    refined[j].crop = model.Crop(T_coarse);
    refined[j].icp = registration.PointToPoint(refined[j].crop.points_model, scene_grid, T_coarse, options.refine_icp);
    refined[j].score =
        ScoreAlignment(refined[j].crop.points_model, refined[j].icp.T_target_source, scene_grid, alignment).score;
  }
  double top = -1.0;
  for (const auto& r : refined) top = std::max(top, r.score);
  int win = 0;
  for (int j = 1; j < count; ++j)
    if (RanksBefore(refined[j].score, refined[j].icp.inlier_rmse_m, refined[win].score,
                    refined[win].icp.inlier_rmse_m, top, options.score_tie))
      win = j;
  // Tied in score and in inlier RMSE (within prior_rmse_tie of the winner's): the depth does not tell the
  // poses apart (a table top anywhere in its plane), so the one nearest the prior is kept, and the slide the
  // depth cannot see is not reported as the estimate's.
  if (prior) {
    const double rmse_bound = refined[win].icp.inlier_rmse_m * (1.0 + options.prior_rmse_tie);
    for (int j = 0; j < count; ++j)
      if (refined[j].score >= top - options.score_tie && refined[j].icp.inlier_rmse_m <= rmse_bound &&
          TranslationDistanceM(refined[j].icp.T_target_source, *prior) <
              TranslationDistanceM(refined[win].icp.T_target_source, *prior))
        win = j;
  }
  result->best = order[win];
  result->refine = refined[win].icp;
  result->refined_crop = std::move(refined[win].crop);
  result->T_camera_model = result->refine.T_target_source;
  result->score = refined[win].score;
}

/// Coarse-to-fine hypothesis pruning (docs/validation.md "Acquisition"), then the epsilon test.
void RunHypotheses(const PointGrid& scene_grid, const CropSource& model, const AcquisitionOptions& options,
                   const AlignmentOptions& alignment, const Rigid3d* prior, AcquisitionResult* result) {
  if (result->hypotheses.empty()) {
    result->reason = "no hypotheses";
    return;
  }
  const std::vector<int> order = RegisterCoarse(scene_grid, options, alignment, result);
  RefineBest(scene_grid, model, options, alignment, order, prior, result);
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
  if (hypothesis_stride < 1) throw InputError("AcquisitionOptions", "hypothesis_stride must be >= 1");
  if (refine_count < 1) throw InputError("AcquisitionOptions", "refine_count must be >= 1");
  if (!(prior_rmse_tie >= 0 && prior_rmse_tie < 1)) throw InputError("AcquisitionOptions", "prior_rmse_tie must lie in [0, 1)");
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

AcquisitionResult Acquire(const PointCloud& scene, const PointGrid& scene_grid, const CropSource& model,
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
  RunHypotheses(scene_grid, model, options, alignment, nullptr, &result);
  return result;
}

AcquisitionResult AcquireAround(const PointCloud& scene, const PointGrid& scene_grid, const CropSource& model,
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
  // The prior where it is, too: the median of a partly seen object (a table top cut by the image) is not
  // the median of its crop, and along directions the depth barely constrains ICP would not find the way back.
  const bool seeded = !result.crops[0].points_model.empty();
  if (seeded) result.hypotheses.push_back({T_camera_model_prior, {}, {}, 0});
  RunHypotheses(scene_grid, model, options, alignment, seeded ? &T_camera_model_prior : nullptr, &result);
  return result;
}

}  // namespace mocap
