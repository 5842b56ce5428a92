#pragma once
// Nearest-neighbour searches repeated as their query points move a little: ICP's correspondences and the
// point-to-plane refinement's, iteration after iteration. Each query point remembers its last search (its
// answer and how far around the query that answer was proven the only scene point), and while the point
// has moved less than the proof covers, the old answer stands without a search. Exact: the same answers
// as a fresh search, up to ties between equidistant points.
#include <Eigen/Core>
#include <cstddef>

#include "validate/point_grid.h"

namespace mocap {

/// One query point's last search: its query, its answer (the hint of the next search;
/// PointGrid::kNoHint for none within the gate) and the radius about the query within which that answer
/// was the only scene point (PointGrid::NearestFrom's clear_m; negative before any search).
struct SearchMemory {
  Eigen::Vector3d query = Eigen::Vector3d::Zero();
  size_t match = PointGrid::kNoHint;
  double clear_m = -1.0;
};

/// The nearest scene point to `query` within `gate_m` (false when none; `last->match` is the answer),
/// reusing the last search while its proof covers the move: a query that moved by `moved` keeps its old
/// match while that match's distance stays below clear - moved (every other point is at least that
/// far), and keeps "none" while gate + moved stays within the clear radius. `*d2` receives the squared
/// distance (m^2) of the match. `start_from_last`: a new search starts from the old match (fewer cells;
/// between equidistant points it keeps the old one), else from scratch (between equidistant points it
/// answers as PointGrid::Nearest does, so a caller that searched that way gets the same answers).
bool NearestRemembered(const PointGrid& scene, const Eigen::Vector3d& query, double gate_m, SearchMemory* last,
                       double* d2, bool start_from_last = true);

}  // namespace mocap
