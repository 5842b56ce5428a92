#include "validate/point_cloud.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/check.h"

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

/// Voxel cells in order of first appearance, found through an open-addressing table kept at most half
/// full: a node-based map allocated a node per cell, which cost more than the rest of a record's scene
/// set-up, and a table sized for every point cleared megabytes for a few thousand cells.
class VoxelCells {
 public:
  /// The index of the cell of `key`, added when new.
  uint32_t Find(uint64_t key) {
    if (2 * (cells_.size() + 1) > slots_.size()) Grow();
    size_t slot = Slot(key);
    while (slots_[slot] != kEmpty && cells_[slots_[slot]].key != key) slot = (slot + 1) & (slots_.size() - 1);
    if (slots_[slot] == kEmpty) {
      slots_[slot] = static_cast<uint32_t>(cells_.size());
      cells_.push_back({key, Eigen::Vector3d::Zero(), 0});
    }
    return slots_[slot];
  }
  void Add(uint32_t cell, const Eigen::Vector3d& p) {
    cells_[cell].sum += p;
    ++cells_[cell].count;
  }
  PointCloud Means() const {
    PointCloud out(cells_.size());
    for (size_t i = 0; i < cells_.size(); ++i) out[i] = cells_[i].sum / cells_[i].count;
    return out;
  }

 private:
  static constexpr uint32_t kEmpty = std::numeric_limits<uint32_t>::max();
  struct Cell {
    uint64_t key;
    Eigen::Vector3d sum;
    int count;
  };
  size_t Slot(uint64_t key) const {
    return static_cast<size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);  // Fibonacci hashing
  }
  void Grow() {
    const size_t capacity = std::max<size_t>(1024, 2 * slots_.size());
    slots_.assign(capacity, kEmpty);
    shift_ = 64 - std::countr_zero(capacity);
    for (size_t i = 0; i < cells_.size(); ++i) {
      size_t slot = Slot(cells_[i].key);
      while (slots_[slot] != kEmpty) slot = (slot + 1) & (capacity - 1);
      slots_[slot] = static_cast<uint32_t>(i);
    }
  }
  std::vector<Cell> cells_;
  std::vector<uint32_t> slots_;
  int shift_ = 64;
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
  VoxelCells cells;
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
    if (key != last_key) last_cell = cells.Find(key), last_key = key;
    cells.Add(last_cell, p);
  }
  return cells.Means();
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
