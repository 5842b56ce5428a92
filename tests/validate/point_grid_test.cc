#include "validate/point_grid.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "synthetic.h"

namespace mocap {
namespace {

/// The nearest point strictly within `max_distance_m` by scanning all of them (float, as the grid stores).
double BruteNearestSq(const PointCloud& cloud, const Eigen::Vector3d& query, double max_distance_m) {
  float best = static_cast<float>(max_distance_m * max_distance_m);
  double found = -1.0;
  for (const auto& p : cloud) {
    const float d = (p.cast<float>() - query.cast<float>()).squaredNorm();
    if (d < best) best = d, found = d;
  }
  return found;
}

/// A box surface with noise plus a few far outliers (a segmentation that leaked), as scene clouds are.
PointCloud SceneLike(std::mt19937& rng) {
  PointCloud cloud = testing::AddNoise(testing::BoxSurface({0.07, 0.09, 0.2}, 0.003), rng, 0.001);
  cloud.push_back({0.3, -0.2, 0.1});
  cloud.push_back({-0.1, 0.25, -0.3});
  return cloud;
}

TEST(PointGrid, NearestMatchesBruteForceNearAndFarFromTheCloud) {
  std::mt19937 rng(7);
  const PointCloud cloud = SceneLike(rng);
  const PointGrid grid(cloud);
  std::uniform_int_distribution<size_t> any(0, grid.size() - 1);
  int found_count = 0, missed_count = 0;
  for (const double spread_m : {0.002, 0.01, 0.04, 0.2}) {
    for (const auto& q : testing::AddNoise(PointCloud(cloud.begin(), cloud.begin() + 600), rng, spread_m)) {
      for (const double gate_m : {0.01, 0.05}) {
        const double expected = BruteNearestSq(cloud, q, gate_m);
        size_t plain = 0, from = any(rng) % 3 == 0 ? PointGrid::kNoHint : any(rng);
        double d2_plain = -1, d2_from = -1;
        ASSERT_EQ(grid.Nearest(q, gate_m, &plain, &d2_plain), expected >= 0) << q.transpose() << " gate " << gate_m;
        ASSERT_EQ(grid.NearestFrom(q, gate_m, &from, &d2_from), expected >= 0);
        if (expected < 0) {
          ++missed_count;
          continue;
        }
        EXPECT_FLOAT_EQ(d2_plain, expected);
        EXPECT_FLOAT_EQ(d2_from, expected);
        EXPECT_NEAR((grid.point(plain) - q).squaredNorm(), expected, 1e-5 * expected + 1e-10);  // float vs double
        ++found_count;
      }
    }
  }
  EXPECT_GT(found_count, 2000);
  EXPECT_GT(missed_count, 500);  // the far queries exercise the empty-ring skip
}

TEST(PointGrid, TheClearRadiusHoldsNoOtherPointAndReachesTheMargin) {
  std::mt19937 rng(9);
  const PointCloud cloud = SceneLike(rng);
  const PointGrid grid(cloud);
  const double margin_m = 0.002;
  int found_count = 0;
  for (const auto& q : testing::AddNoise(PointCloud(cloud.begin(), cloud.begin() + 500), rng, 0.01)) {
    size_t index = PointGrid::kNoHint;
    double d2 = 0, clear_m = 0;
    const bool found = grid.NearestFrom(q, 0.01, margin_m, &index, &d2, &clear_m);
    ASSERT_EQ(found, BruteNearestSq(cloud, q, 0.01) >= 0);
    // Brute force: the nearest point other than the match (all points when none was found).
    double other_m = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < grid.size(); ++i)
      if (!found || i != index) other_m = std::min(other_m, (grid.point(i) - q).norm());
    EXPECT_LE(clear_m, other_m + 1e-6);
    const double nearest_m = found ? std::sqrt(d2) : 0.01;
    EXPECT_GE(clear_m, std::min(other_m, nearest_m + margin_m) - 1e-6);  // what the margin asks for
    found_count += found;
  }
  EXPECT_GT(found_count, 200);
}

TEST(PointGrid, RadiusMatchesBruteForceSorted) {
  std::mt19937 rng(8);
  const PointCloud cloud = SceneLike(rng);
  const PointGrid grid(cloud);
  std::vector<std::pair<size_t, float>> out;
  for (const auto& q : testing::AddNoise(PointCloud(cloud.begin(), cloud.begin() + 300), rng, 0.005)) {
    grid.Radius(q, 0.01, &out);
    size_t expected = 0;
    for (const auto& p : cloud) expected += (p.cast<float>() - q.cast<float>()).squaredNorm() < 1e-4f;
    ASSERT_EQ(out.size(), expected);
    for (size_t k = 1; k < out.size(); ++k) EXPECT_LE(out[k - 1].second, out[k].second);
    for (const auto& [index, d2] : out) EXPECT_NEAR((grid.point(index) - q).squaredNorm(), d2, 1e-5 * d2 + 1e-10);
  }
}

TEST(PointGrid, NearestUntakenIsTheFirstFreeEntryOfRadius) {
  std::mt19937 rng(10);
  const PointCloud cloud = SceneLike(rng);
  const PointGrid grid(cloud);
  std::vector<char> taken(grid.size(), 0);
  std::bernoulli_distribution take(0.6);
  for (char& t : taken) t = take(rng);
  std::vector<std::pair<size_t, float>> near;
  int found = 0, none = 0;
  for (const auto& q : testing::AddNoise(PointCloud(cloud.begin(), cloud.begin() + 400), rng, 0.004))
    for (const double max_sq : {1e-4, 4e-6}) {
      grid.Radius(q, 0.01, &near);
      size_t expected = PointGrid::kNoHint;
      for (const auto& [index, d2] : near)
        if (!taken[index] && static_cast<double>(d2) <= max_sq) {
          expected = index;
          break;
        }
      size_t index = PointGrid::kNoHint;
      ASSERT_EQ(grid.NearestUntaken(q, 0.01, taken, max_sq, &index), expected != PointGrid::kNoHint) << q.transpose();
      EXPECT_EQ(index, expected);
      (expected == PointGrid::kNoHint ? none : found) += 1;
    }
  EXPECT_GT(found, 300);  // both answers occur
  EXPECT_GT(none, 20);
  size_t index = 0;
  EXPECT_FALSE(PointGrid(PointCloud{}).NearestUntaken({0, 0, 0}, 0.01, {}, 1.0, &index));
}

TEST(PointGrid, AnyWithinAgreesWithNearest) {
  std::mt19937 rng(9);
  const PointCloud cloud = SceneLike(rng);
  const PointGrid grid(cloud);
  PointCloud queries = testing::AddNoise(PointCloud(cloud.begin(), cloud.begin() + 400), rng, 0.006);
  queries.push_back({5.0, 5.0, 5.0});    // beyond the grid
  queries.push_back({1e9, 0.0, 0.0});    // beyond the grid's cell coordinates
  int found = 0;
  for (const auto& q : queries)
    for (const double radius_m : {0.001, 0.004, 0.02}) {
      size_t index = 0;
      double d2 = 0;
      const bool nearest = grid.Nearest(q, radius_m, &index, &d2);
      ASSERT_EQ(grid.AnyWithin(q, radius_m), nearest) << q.transpose() << " within " << radius_m;
      found += nearest;
    }
  EXPECT_GT(found, 300);  // both answers occur
  EXPECT_LT(found, 3 * static_cast<int>(queries.size()));
}

TEST(PointGrid, OutliersEnlargeTheCellsInsteadOfTheGrid) {
  PointCloud cloud = testing::BoxSurface({0.1, 0.1, 0.1}, 0.01);
  cloud.push_back({50.0, 50.0, 50.0});  // 50 m away: 6 mm cells would need 10^12 of them
  const PointGrid grid(cloud);
  EXPECT_GT(grid.cell_m(), 0.5);
  size_t index = 0;
  double d2 = 0;
  ASSERT_TRUE(grid.Nearest({0.05, 0.05, 0.051}, 0.01, &index, &d2));
  EXPECT_NEAR(d2, 1e-6, 1e-9);
  EXPECT_TRUE(grid.Nearest({50.0, 50.0, 50.005}, 0.01, &index, &d2));
}

TEST(PointGrid, EmptyCloudAndQueriesFarAwayFindNothing) {
  const PointGrid empty(PointCloud{});
  size_t index = 0;
  double d2 = 0;
  EXPECT_FALSE(empty.Nearest({0, 0, 0}, 1.0, &index, &d2));
  const PointGrid one(PointCloud{{0, 0, 1}});
  EXPECT_FALSE(one.Nearest({0, 0, 1.02}, 0.01, &index, &d2));
  EXPECT_FALSE(one.Nearest({1e12, 0, 0}, 0.01, &index, &d2));
  EXPECT_TRUE(one.Nearest({1e9, 0, 0}, 1e10, &index, &d2));  // beyond the cell range: scanned in full
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(one.Nearest({nan, 0, 1}, 0.01, &index, &d2));
  EXPECT_THROW(PointGrid(PointCloud{}, PointGridOptions{.cell_m = 0}), InputError);
}

}  // namespace
}  // namespace mocap
