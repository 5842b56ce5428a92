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
  if (!points_.empty()) index_->buildIndex();
}

KdTree::~KdTree() = default;

bool KdTree::Nearest(const Eigen::Vector3d& query, size_t* index, double* distance_sq_m2) const {
  if (points_.empty()) return false;
  const Eigen::Vector3f q = query.cast<float>();
  size_t found = 0;
  float distance_sq = 0.0f;
  nanoflann::KNNResultSet<float, size_t> result(1);
  result.init(&found, &distance_sq);
  index_->findNeighbors(result, q.data(), nanoflann::SearchParams());
  *index = found;
  *distance_sq_m2 = distance_sq;
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
