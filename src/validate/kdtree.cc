#include "validate/kdtree.h"

#include <nanoflann.hpp>

namespace mocap {

struct KdTree::Adaptor {
  const std::vector<Eigen::Vector3f>* points;
  size_t kdtree_get_point_count() const { return points->size(); }
  float kdtree_get_pt(size_t i, size_t dim) const { return (*points)[i][static_cast<int>(dim)]; }
  template <class Bbox>
  bool kdtree_get_bbox(Bbox&) const {
    return false;
  }
};

struct KdTree::Index
    : nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, KdTree::Adaptor, float, size_t>,
                                          KdTree::Adaptor, 3, size_t> {
  using Base = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, KdTree::Adaptor, float, size_t>,
                                                   KdTree::Adaptor, 3, size_t>;
  using Base::Base;
};

KdTree::KdTree(const PointCloud& points, int leaf_max_size) : points_(points.size()) {
  for (size_t i = 0; i < points.size(); ++i) points_[i] = points[i].cast<float>();
  adaptor_ = std::make_unique<Adaptor>(Adaptor{&points_});
  index_ = std::make_unique<Index>(3, *adaptor_,
                                   nanoflann::KDTreeSingleIndexAdaptorParams(static_cast<size_t>(leaf_max_size)));
  if (points_.empty()) return;
  index_->buildIndex();
  // Store the points in the tree's leaf order, so that a leaf's points are contiguous in memory (the
  // search scans leaves); the tree then indexes them through the identity permutation.
  std::vector<Eigen::Vector3f> ordered(points_.size());
  for (size_t j = 0; j < ordered.size(); ++j) ordered[j] = points_[index_->vAcc[j]];
  points_.swap(ordered);
  for (size_t j = 0; j < points_.size(); ++j) index_->vAcc[j] = j;
}

KdTree::~KdTree() = default;

namespace {

/// nanoflann result set for the single nearest point within a bound: the bound is the initial worst
/// distance, so subtrees beyond it are never visited.
class NearestWithin {
 public:
  explicit NearestWithin(float bound_sq) : best_sq_(bound_sq) {}
  /// Starts from a known point at `distance_sq` (<= the bound): only strictly closer points replace it.
  NearestWithin(float distance_sq, size_t index) : best_sq_(distance_sq), index_(index), found_(true) {}
  size_t size() const { return found_ ? 1 : 0; }
  bool full() const { return true; }
  bool addPoint(float distance_sq, size_t index) {
    if (distance_sq < best_sq_) {
      best_sq_ = distance_sq;
      index_ = index;
      found_ = true;
    }
    return true;
  }
  float worstDist() const { return best_sq_; }
  bool found() const { return found_; }
  size_t index() const { return index_; }

 private:
  float best_sq_;
  size_t index_ = 0;
  bool found_ = false;
};

}  // namespace

bool KdTree::Nearest(const Eigen::Vector3d& query, double max_distance_m, size_t* index,
                     double* distance_sq_m2) const {
  if (points_.empty()) return false;
  const Eigen::Vector3f q = query.cast<float>();
  NearestWithin result(static_cast<float>(max_distance_m * max_distance_m));
  index_->findNeighbors(result, q.data(), nanoflann::SearchParams());
  if (!result.found()) return false;
  *index = result.index();
  *distance_sq_m2 = (points_[result.index()] - q).squaredNorm();
  return true;
}

bool KdTree::NearestFrom(const Eigen::Vector3d& query, double max_distance_m, size_t* index,
                         double* distance_sq_m2) const {
  if (points_.empty()) return false;
  const Eigen::Vector3f q = query.cast<float>();
  const float bound_sq = static_cast<float>(max_distance_m * max_distance_m);
  const float hint_sq = *index < points_.size() ? (points_[*index] - q).squaredNorm() : bound_sq;
  NearestWithin result = hint_sq < bound_sq ? NearestWithin(hint_sq, *index) : NearestWithin(bound_sq);
  index_->findNeighbors(result, q.data(), nanoflann::SearchParams());
  if (!result.found()) return false;
  *index = result.index();
  *distance_sq_m2 = (points_[result.index()] - q).squaredNorm();
  return true;
}

void KdTree::Radius(const Eigen::Vector3d& query, double radius_m,
                    std::vector<std::pair<size_t, float>>* out) const {
  out->clear();
  if (points_.empty()) return;
  const Eigen::Vector3f q = query.cast<float>();
  // nanoflann's L2 adaptors take the squared radius.
  index_->radiusSearch(q.data(), static_cast<float>(radius_m * radius_m), *out, nanoflann::SearchParams(32, 0, true));
}

}  // namespace mocap
