#pragma once
// A 3-D kd-tree over a scene cloud (nanoflann). Points are stored as float: the queries are memory
// bound and float halves the footprint; distances are returned in double, metres squared.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "validate/point_cloud.h"

namespace mocap {

class KdTree {
 public:
  /// Builds the tree over a copy of `points` (may be empty: every query then finds nothing).
  explicit KdTree(const PointCloud& points, int leaf_max_size = 10);
  ~KdTree();
  KdTree(const KdTree&) = delete;
  KdTree& operator=(const KdTree&) = delete;

  size_t size() const { return points_.size(); }
  /// Indices (`point`, `Nearest`, `Radius`) number the points in the tree's own order, not the input's:
  /// the stored copy is reordered so that each leaf's points are contiguous.
  /// The stored point `index` (float precision), metres.
  Eigen::Vector3d point(size_t index) const { return points_[index].cast<double>(); }

  /// Nearest stored point to `query` strictly within `max_distance_m`: returns false when there is none.
  /// The bound prunes the descent, which makes queries far from the cloud (bad hypotheses) cheap.
  bool Nearest(const Eigen::Vector3d& query, double max_distance_m, size_t* index, double* distance_sq_m2) const;

  /// The same search started from a guess: `*index` holds a stored point believed near the query (the
  /// previous ICP iteration's match) or kNoHint. The nearest point is no farther than the guess, so the
  /// guess's distance bounds the descent from the start and far fewer subtrees are visited; the result
  /// is that of Nearest (up to ties).
  bool NearestFrom(const Eigen::Vector3d& query, double max_distance_m, size_t* index, double* distance_sq_m2) const;
  static constexpr size_t kNoHint = static_cast<size_t>(-1);

  /// All stored points within `radius_m`, sorted by increasing distance, as (index, distance^2).
  void Radius(const Eigen::Vector3d& query, double radius_m, std::vector<std::pair<size_t, float>>* out) const;

 private:
  struct Adaptor;
  struct Index;
  std::vector<Eigen::Vector3f> points_;
  std::unique_ptr<Adaptor> adaptor_;
  std::unique_ptr<Index> index_;
};

}  // namespace mocap
