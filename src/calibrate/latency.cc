#include "calibrate/latency.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "calibrate/robust_stats.h"
#include "core/check.h"

namespace mocap {
namespace {

struct FramePair {
  int64_t t_a_ns = 0, t_b_ns = 0;
  double image_turn_deg = 0;
};

/// Each frame with the first later frame at least interval_ns after it.
std::vector<FramePair> MakePairs(std::span<const StampedBoardPose> poses, int64_t interval_ns) {
  std::vector<FramePair> pairs;
  size_t b = 0;
  for (size_t a = 0; a < poses.size(); ++a) {
    b = std::max(b, a + 1);
    while (b < poses.size() && poses[b].stamp_ns - poses[a].stamp_ns < interval_ns) ++b;
    if (b == poses.size()) break;
    pairs.push_back({poses[a].stamp_ns, poses[b].stamp_ns, RotationDistanceDeg(poses[a].T_camera_board, poses[b].T_camera_board)});
  }
  return pairs;
}

std::optional<double> TrackerTurnDeg(const FramePair& pair, double latency_ns, const RelativePoseAt& at) {
  const int64_t shift = std::llround(latency_ns);
  const std::optional<Rigid3d> a = at(pair.t_a_ns + shift);
  if (!a) return std::nullopt;
  const std::optional<Rigid3d> b = at(pair.t_b_ns + shift);
  if (!b) return std::nullopt;
  return RotationDistanceDeg(*a, *b);
}

/// RMS angle disagreement (degrees) over the pairs with tracker data at this latency; NaN when none.
double CostDeg(const std::vector<FramePair>& pairs, double latency_ns, const RelativePoseAt& at) {
  double sum = 0;
  int count = 0;
  for (const FramePair& pair : pairs)
    if (const std::optional<double> turn = TrackerTurnDeg(pair, latency_ns, at)) {
      sum += std::pow(*turn - pair.image_turn_deg, 2);
      ++count;
    }
  return count == 0 ? std::numeric_limits<double>::quiet_NaN() : std::sqrt(sum / count);
}

/// The pairs with tracker data at every grid latency: the cost then compares like with like.
std::vector<FramePair> PairsValidOverGrid(const std::vector<FramePair>& pairs, const std::vector<int64_t>& grid_ns,
                                          const RelativePoseAt& at) {
  std::vector<FramePair> kept;
  for (const FramePair& pair : pairs) {
    bool valid = true;
    for (size_t g = 0; g < grid_ns.size() && valid; ++g) valid = TrackerTurnDeg(pair, static_cast<double>(grid_ns[g]), at).has_value();
    if (valid) kept.push_back(pair);
  }
  return kept;
}

/// Golden-section search for the minimum of cost on [lo, hi] down to a bracket of tolerance.
double GoldenSection(const std::function<double(double)>& cost, double lo, double hi, double tolerance) {
  const double inv_phi = (std::sqrt(5.0) - 1) / 2;
  double x1 = hi - inv_phi * (hi - lo), x2 = lo + inv_phi * (hi - lo);
  double f1 = cost(x1), f2 = cost(x2);
  while (hi - lo > tolerance) {
    if (f1 < f2) {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - inv_phi * (hi - lo), f1 = cost(x1);
    } else {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + inv_phi * (hi - lo), f2 = cost(x2);
    }
  }
  return 0.5 * (lo + hi);
}

void AddWarnings(const LatencyOptions& options, size_t best_index, size_t grid_size, LatencyResult& result) {
  if (result.turn_rms_deg < options.min_turn_deg)
    result.warnings.push_back(Str("the board hardly turns relative to the camera (", result.turn_rms_deg, " degrees RMS per ",
                                  options.pair_interval_ns / 1'000'000, " ms): record quick back-and-forth turns of the "
                                  "board (or camera), 1-2 Hz through 20-40 degrees, about changing axes"));
  if (result.contrast < options.min_contrast)
    result.warnings.push_back(Str("no distinct latency: the disagreement at the best latency is ", result.rms_deg,
                                  " degrees against a median of ", result.contrast * result.rms_deg,
                                  "; record faster, jerkier turns with the board sharp in every frame"));
  if (best_index == 0 || best_index + 1 == grid_size)
    result.warnings.push_back(Str("the best latency lies at the edge of the search range (+-",
                                  options.search_half_range_ns / 1'000'000, " ms): widen it or check the clocks"));
}

}  // namespace

RelativePoseAt RelativePoseFromStreams(std::vector<PoseSample> cambody, std::vector<PoseSample> boardbody,
                                       const InterpolationOptions& interpolation) {
  interpolation.check();
  return [cambody = std::move(cambody), boardbody = std::move(boardbody), interpolation](int64_t t_ns) -> std::optional<Rigid3d> {
    const InterpolatedPose camera_body = InterpolatePose(cambody, t_ns, interpolation);
    const InterpolatedPose board_body = InterpolatePose(boardbody, t_ns, interpolation);
    if (!camera_body.ok() || !board_body.ok()) return std::nullopt;
    return camera_body.pose->inverse() * *board_body.pose;
  };
}

void LatencyOptions::check() const {
  if (search_half_range_ns <= 0) throw InputError("LatencyOptions.search_half_range_ns", "must be positive");
  if (coarse_step_ns <= 0 || coarse_step_ns > search_half_range_ns)
    throw InputError("LatencyOptions.coarse_step_ns", "must be positive and at most search_half_range_ns");
  if (pair_interval_ns <= 0) throw InputError("LatencyOptions.pair_interval_ns", "must be positive");
  if (tolerance_ns <= 0) throw InputError("LatencyOptions.tolerance_ns", "must be positive");
  if (min_pairs < 3) throw InputError("LatencyOptions.min_pairs", Str("is ", min_pairs, "; need >= 3"));
  if (!(min_contrast >= 1)) throw InputError("LatencyOptions.min_contrast", "must be >= 1");
  if (!(min_turn_deg >= 0)) throw InputError("LatencyOptions.min_turn_deg", "must be >= 0");
}

LatencyResult EstimateTrackerLatency(std::span<const StampedBoardPose> image_poses, const RelativePoseAt& T_cambody_boardbody_at,
                                     const LatencyOptions& options) {
  options.check();
  std::vector<int64_t> grid_ns;
  for (int64_t l = -options.search_half_range_ns; l <= options.search_half_range_ns; l += options.coarse_step_ns) grid_ns.push_back(l);
  const std::vector<FramePair> all_pairs = MakePairs(image_poses, options.pair_interval_ns);
  const std::vector<FramePair> pairs = PairsValidOverGrid(all_pairs, grid_ns, T_cambody_boardbody_at);
  if (static_cast<int>(pairs.size()) < options.min_pairs)
    throw InputError("latency", Str("too few frame pairs with tracker data at every latency searched: ", pairs.size(), " of ",
                                    all_pairs.size(), " (need ", options.min_pairs, "); record longer (10 s or more) "
                                    "with both bodies tracked throughout, starting the tracker before the camera"));
  LatencyResult result;
  result.pairs_used = static_cast<int>(pairs.size());
  std::vector<double> costs;
  for (int64_t l : grid_ns) {
    costs.push_back(CostDeg(pairs, static_cast<double>(l), T_cambody_boardbody_at));
    result.coarse_cost_deg.emplace_back(l, costs.back());
  }
  const size_t best = static_cast<size_t>(std::min_element(costs.begin(), costs.end()) - costs.begin());
  const auto cost = [&](double l) { return CostDeg(pairs, l, T_cambody_boardbody_at); };
  const double lo = static_cast<double>(grid_ns[best > 0 ? best - 1 : 0]);
  const double hi = static_cast<double>(grid_ns[std::min(best + 1, grid_ns.size() - 1)]);
  const double latency_ns = GoldenSection(cost, lo, hi, static_cast<double>(options.tolerance_ns));
  result.tracker_latency_ns = std::llround(latency_ns);
  result.rms_deg = cost(latency_ns);
  result.contrast = Median(costs) / std::max(result.rms_deg, 1e-12);
  double turn2 = 0;
  for (const FramePair& pair : pairs) turn2 += pair.image_turn_deg * pair.image_turn_deg;
  result.turn_rms_deg = std::sqrt(turn2 / static_cast<double>(pairs.size()));
  AddWarnings(options, best, grid_ns.size(), result);
  return result;
}

}  // namespace mocap
