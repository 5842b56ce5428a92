#pragma once
// Exact nearest-neighbour queries within a small radius, by a dense grid of cubic cells over the
// cloud's bounding box: the validator's scene index. Every query of the validator is bounded by a gate
// of 1-5 cm around a point that is usually a few millimetres from the surface (ICP correspondences,
// the alignment score), where a kd-tree spends most of its work descending and backtracking. Here a
// query visits the cells around it in rings of growing Chebyshev distance and stops as soon as the
// next ring lies farther than the best point found; a chessboard distance transform over the cells
// (over blocks of 2^3 cells) lets a query far from every point skip the empty rings (or answer "none"
// at once). kiss-icp indexes its map the same way with a voxel hash; a dense array suffices for one
// object's cloud.
//
// Same interface and results as KdTree (up to ties); bench/bench_validate.cc compares the two.
#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

#include "validate/point_cloud.h"

namespace mocap {

struct PointGridOptions {
  /// Cell edge, metres. A few scene voxels (3 mm): a query near the surface then finds its nearest
  /// point in its own cell or the next ring, and a cell holds a handful of points. On the benchmark's
  /// real scene 8 mm took the fewest instructions (4-10 mm lie within 5 % of each other).
  double cell_m = 0.008;
  /// The grid holds at most this many cells per point (plus 4,096): a cloud with far outliers gets
  /// larger cells rather than a grid that fills the memory. Queries stay exact, only slower.
  double max_cells_per_point = 8.0;
  /// Throws InputError on a non-positive cell or cell budget.
  void check() const;
};

class PointGrid {
 public:
  /// Indexes a copy of `points` (may be empty: every query then finds nothing).
  explicit PointGrid(const PointCloud& points, const PointGridOptions& options = {});

  size_t size() const { return points_.size(); }
  /// Indices (`point`, `Nearest`, `Radius`) number the points in the grid's own order (cell by cell),
  /// not the input's. The stored point `index` (float precision), metres.
  Eigen::Vector3d point(size_t index) const { return points_[index].cast<double>(); }
  /// The cell edge in use (options.cell_m or larger, see max_cells_per_point), metres.
  double cell_m() const { return cell_m_; }
  /// A number no other grid built in this process has (a copy keeps it: it holds the same points), so
  /// that a registration backend can cache its own index of the scene per grid (validate/registration.h);
  /// an address could be reused by the next scene's grid.
  uint64_t id() const { return id_; }

  /// Nearest stored point to `query` strictly within `max_distance_m`: returns false when there is none.
  bool Nearest(const Eigen::Vector3d& query, double max_distance_m, size_t* index, double* distance_sq_m2) const;

  /// The same search started from a guess: `*index` holds a stored point believed near the query (the
  /// previous ICP iteration's match) or kNoHint. The guess's distance bounds the search from the start,
  /// so a query whose guess is still close visits one or two cells.
  bool NearestFrom(const Eigen::Vector3d& query, double max_distance_m, size_t* index, double* distance_sq_m2) const;
  static constexpr size_t kNoHint = static_cast<size_t>(-1);

  /// NearestFrom that also tells how far its answer holds: *clear_m receives a radius about the query
  /// within which the returned point is the only stored point (within which there is none, when none
  /// is returned). The search examines the points up to `margin_m` beyond the nearest for it, so that a
  /// caller whose query has moved by `moved` since knows, while its old match's distance stays below
  /// clear - moved, that the old match is still the nearest (ICP's late iterations, validate/icp.cc).
  bool NearestFrom(const Eigen::Vector3d& query, double max_distance_m, double margin_m, size_t* index,
                   double* distance_sq_m2, double* clear_m) const;

  /// Whether some stored point lies strictly within `radius_m` of `query` (as Nearest finds one): stops
  /// at the first, for callers that count supported points (the observability probe).
  bool AnyWithin(const Eigen::Vector3d& query, double radius_m) const;

  /// All stored points strictly within `radius_m`, sorted by increasing distance, as (index, distance^2).
  void Radius(const Eigen::Vector3d& query, double radius_m, std::vector<std::pair<size_t, float>>* out) const;

  /// The first entry of Radius's answer (nearest first, ties to the lower index) that is not `taken`
  /// and lies within sqrt(max_distance_sq_m2) too, without collecting and sorting the neighbourhood (the
  /// alignment score's fallback when a point's nearest is already claimed). False when there is none.
  bool NearestUntaken(const Eigen::Vector3d& query, double radius_m, const std::vector<char>& taken,
                      double max_distance_sq_m2, size_t* index) const;

  /// A search's running answer (internal): the nearest point so far (index kNone while none lies
  /// within the bound sq) and the nearest of the other points examined.
  struct Best {
    float sq;
    uint32_t index;
    float second_sq;
  };

 private:
  /// Examines the points as far as needed to find the nearest strictly within sqrt(best->sq) and every
  /// point within `margin_m` beyond it; updates *best. Returns the radius about the query within
  /// which every point was examined.
  float Search(const Eigen::Vector3f& query, float margin_m, Best* best) const;
  /// Scans the cells of ring `ring` around `cell` that lie within the clamped box [lo, hi].
  void ScanRing(const Eigen::Vector3f& query, const Eigen::Vector3i& cell, int ring, const Eigen::Vector3i& lo,
                const Eigen::Vector3i& hi, Best* best) const;
  /// The lowest ring around `cell` (any cell, inside the grid or not) that can hold a point.
  int FirstRing(const Eigen::Vector3i& cell) const;
  /// The cells [lo, hi] that can hold a point within `radius_m` of `query` (RadiusCells false: none).
  bool RadiusCells(const Eigen::Vector3f& query, float radius_m, Eigen::Vector3i* lo, Eigen::Vector3i* hi) const;
  void ComputeEmptyRings();
  /// Index into empty_rings_ of the block holding grid cell (x, y, z).
  size_t PaddedBlock(int x, int y, int z) const;
  size_t CellIndex(int x, int y, int z) const {
    return (static_cast<size_t>(z) * static_cast<size_t>(dims_.y()) + static_cast<size_t>(y)) *
               static_cast<size_t>(dims_.x()) + static_cast<size_t>(x);
  }

  std::vector<Eigen::Vector3f> points_;  ///< sorted by cell
  std::vector<uint32_t> cell_start_;     ///< cell c holds points_[cell_start_[c], cell_start_[c + 1])
  /// Per block of cells (padded by one), the chessboard distance in blocks to a non-empty block (<= 255).
  std::vector<uint8_t> empty_rings_;
  Eigen::Vector3i block_dims_ = Eigen::Vector3i::Zero();
  Eigen::Vector3f origin_ = Eigen::Vector3f::Zero();  ///< corner of cell (0, 0, 0), metres
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  float cell_m_ = 0.0f;
  float inv_cell_ = 0.0f;
  uint64_t id_ = 0;
};

}  // namespace mocap
