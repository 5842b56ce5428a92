#include "validate/search_memory.h"

namespace mocap {
namespace {

/// How far beyond its nearest point each search proves that point unique. A wider proof lasts more
/// iterations but costs every search more cells: on the benchmark's real scene (3 mm voxels) 0.5-1 mm
/// took the fewest instructions; 2-3 mm gained less.
constexpr double kProofMargin_m = 0.001;

/// The grid computes in float: proofs lose this much.
constexpr double kRounding_m = 1e-6;

}  // namespace

bool NearestRemembered(const PointGrid& scene, const Eigen::Vector3d& query, double gate_m, SearchMemory* last,
                       double* d2, bool start_from_last) {
  const double moved_m = (query - last->query).norm();
  const double clear_m = last->clear_m - moved_m - kRounding_m;
  if (last->match != PointGrid::kNoHint && clear_m > 0) {
    *d2 = (scene.point(last->match) - query).squaredNorm();
    if (*d2 < clear_m * clear_m) return *d2 <= gate_m * gate_m;
  } else if (last->match == PointGrid::kNoHint && gate_m <= clear_m) {
    return false;
  }
  last->query = query;
  if (!start_from_last) last->match = PointGrid::kNoHint;
  const bool found = scene.NearestFrom(query, gate_m, kProofMargin_m, &last->match, d2, &last->clear_m);
  if (!found) last->match = PointGrid::kNoHint;
  return found && *d2 <= gate_m * gate_m;
}

}  // namespace mocap
