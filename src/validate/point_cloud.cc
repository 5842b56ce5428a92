#include "validate/point_cloud.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/check.h"
#include "validate/first_seen_index.h"

namespace mocap {
namespace {

/// std::floor to an integer without the libm call (x86-64 without SSE4.1 does not inline it, and
/// thinning floors three coordinates per point). NaN and |x| >= 2^62 give 0 rather than an undefined
/// conversion; the key's 21 bits per axis wrap anything beyond a million voxels anyway.
int64_t FloorToInt64(double x) {
  if (!(std::abs(x) < 0x1p62)) return 0;
  const auto truncated = static_cast<int64_t>(x);  // toward zero
  return truncated - (x < static_cast<double>(truncated));
}

struct VoxelKeyHash {
  uint64_t operator()(uint64_t key) const { return MixBits(key); }
};

}  // namespace

Eigen::Vector3d ComponentMedian(const PointCloud& points) {
  MOCAP_CHECK(!points.empty(), "median of an empty cloud");
  Eigen::Vector3d median;
  std::vector<double> values(points.size());
  for (int axis = 0; axis < 3; ++axis) {
    for (size_t i = 0; i < points.size(); ++i) values[i] = points[i][axis];
    auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
    std::nth_element(values.begin(), middle, values.end());
    median[axis] = *middle;
  }
  return median;
}

Eigen::Vector3d Centroid(const PointCloud& points) {
  MOCAP_CHECK(!points.empty(), "centroid of an empty cloud");
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

PointCloud Transform(const Rigid3d& T_a_b, const PointCloud& points_b) {
  const Eigen::Matrix3d R = T_a_b.rotation_matrix();
  const Eigen::Vector3d t = T_a_b.translation();
  PointCloud points_a(points_b.size());
  for (size_t i = 0; i < points_b.size(); ++i) points_a[i] = R * points_b[i] + t;
  return points_a;
}

PointCloud VoxelDownsample(const PointCloud& points, double voxel_m) {
  if (voxel_m <= 0.0) return points;
  struct Cell {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
  };
  FirstSeenIndex<uint64_t, VoxelKeyHash> index;  // cells in order of first appearance
  std::vector<Cell> cells;
  const double inv = 1.0 / voxel_m;
  // A cloud back-projected from a depth image comes row by row, and neighbouring pixels mostly share a
  // voxel: the previous point's cell is tried before the table.
  uint64_t last_key = ~uint64_t{0};
  uint32_t last_cell = 0;
  for (const auto& p : points) {
    // 21 bits per axis (+-1 million voxels) is far beyond any camera range at millimetre voxels.
    const auto key_of = [&](int axis) {
      return static_cast<uint64_t>(FloorToInt64(p[axis] * inv) + (1 << 20)) & 0x1FFFFF;
    };
    const uint64_t key = key_of(0) | (key_of(1) << 21) | (key_of(2) << 42);
    if (key != last_key) {
      const auto [cell, fresh] = index.Insert(key);
      if (fresh) cells.emplace_back();
      last_cell = cell, last_key = key;
    }
    cells[last_cell].sum += p;
    ++cells[last_cell].count;
  }
  PointCloud out(cells.size());
  for (size_t i = 0; i < cells.size(); ++i) out[i] = cells[i].sum / cells[i].count;
  return out;
}

Box3d BoundingBox(const PointCloud& points, double margin_m) {
  Box3d box;
  if (points.empty()) return box;
  box.min = box.max = points.front();
  for (const auto& p : points) {
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  box.min.array() -= margin_m;
  box.max.array() += margin_m;
  return box;
}

PointCloud CropToBox(const PointCloud& scene, const Rigid3d& T_scene_model, const Box3d& box_model) {
  const Rigid3d T_model_scene = T_scene_model.inverse();
  const Eigen::Matrix3d R = T_model_scene.rotation_matrix();
  const Eigen::Vector3d t = T_model_scene.translation();
  PointCloud kept;
  for (const auto& p : scene)
    if (box_model.contains(R * p + t)) kept.push_back(p);
  return kept;
}

}  // namespace mocap
