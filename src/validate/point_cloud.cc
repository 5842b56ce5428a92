#include "validate/point_cloud.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/check.h"

namespace mocap {

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
  // Cells in order of first appearance, found through an open-addressing table at most half full: a
  // node-based map allocated a node per cell, which cost more than the rest of a record's scene set-up.
  struct Cell {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
  };
  std::vector<Cell> cells;
  cells.reserve(points.size());
  size_t capacity = 16;
  while (capacity < 2 * points.size()) capacity *= 2;
  constexpr uint32_t kEmpty = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> slot_cell(capacity, kEmpty);
  std::vector<uint64_t> slot_key(capacity);
  const int shift = 64 - std::countr_zero(capacity);
  const double inv = 1.0 / voxel_m;
  for (const auto& p : points) {
    // 21 bits per axis (+-1 million voxels) is far beyond any camera range at millimetre voxels.
    const auto key_of = [&](int axis) {
      return static_cast<uint64_t>(static_cast<int64_t>(std::floor(p[axis] * inv)) + (1 << 20)) & 0x1FFFFF;
    };
    const uint64_t key = key_of(0) | (key_of(1) << 21) | (key_of(2) << 42);
    size_t slot = static_cast<size_t>((key * 0x9E3779B97F4A7C15ull) >> shift);  // Fibonacci hashing
    while (slot_cell[slot] != kEmpty && slot_key[slot] != key) slot = (slot + 1) & (capacity - 1);
    if (slot_cell[slot] == kEmpty) {
      slot_cell[slot] = static_cast<uint32_t>(cells.size());
      slot_key[slot] = key;
      cells.emplace_back();
    }
    Cell& cell = cells[slot_cell[slot]];
    cell.sum += p;
    ++cell.count;
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
