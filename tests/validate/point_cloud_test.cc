#include "validate/point_cloud.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <tuple>

namespace mocap {
namespace {

// Cells keyed by their integer coordinates, in order of first appearance, the mean of their points:
// what VoxelDownsample returns, by the plainest means.
PointCloud VoxelMeansByMap(const PointCloud& points, double voxel_m) {
  std::map<std::tuple<long, long, long>, size_t> cell_of;
  std::vector<std::pair<Eigen::Vector3d, int>> cells;
  for (const Eigen::Vector3d& p : points) {
    const auto key = std::make_tuple(static_cast<long>(std::floor(p.x() / voxel_m)), static_cast<long>(std::floor(p.y() / voxel_m)),
                                     static_cast<long>(std::floor(p.z() / voxel_m)));
    const auto [it, fresh] = cell_of.try_emplace(key, cells.size());
    if (fresh) cells.emplace_back(Eigen::Vector3d::Zero(), 0);
    cells[it->second].first += p;
    ++cells[it->second].second;
  }
  PointCloud out;
  for (const auto& [sum, count] : cells) out.push_back(sum / count);
  return out;
}

TEST(VoxelDownsample, GivesEachCellsMeanInOrderOfFirstAppearance) {
  std::mt19937 rng(11);
  // Both signs (cells either side of zero), and many points per cell (every cell's chain collides).
  std::uniform_real_distribution<double> coordinate(-0.05, 0.05);
  for (const size_t n : {size_t{0}, size_t{1}, size_t{7}, size_t{5000}}) {
    PointCloud points(n);
    for (Eigen::Vector3d& p : points) p = Eigen::Vector3d(coordinate(rng), coordinate(rng), 0.8 + coordinate(rng));
    const double voxel_m = 0.004;
    const PointCloud thinned = VoxelDownsample(points, voxel_m), expected = VoxelMeansByMap(points, voxel_m);
    ASSERT_EQ(thinned.size(), expected.size()) << n << " points";
    for (size_t i = 0; i < thinned.size(); ++i) EXPECT_LT((thinned[i] - expected[i]).norm(), 1e-12) << "cell " << i;
  }
}

TEST(VoxelDownsample, ZeroVoxelKeepsEveryPoint) {
  const PointCloud points = {Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(0.1, 0.2, 0.3)};
  EXPECT_EQ(VoxelDownsample(points, 0.0), points);
}

}  // namespace
}  // namespace mocap
