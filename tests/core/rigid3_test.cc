#include "core/rigid3.h"

#include <gtest/gtest.h>

#include <numbers>

namespace mocap {
namespace {

TEST(Rigid3, ComposesAsNamedByFrames) {
  // T_a_c = T_a_b * T_b_c: a point at the origin of c lands at T_a_b applied to T_b_c's translation.
  const Rigid3d T_a_b = Rigid3d::FromRvec({0, 0, std::numbers::pi / 2}, {1, 0, 0});
  const Rigid3d T_b_c = Rigid3d::FromRvec({0, 0, 0}, {1, 0, 0});
  const Eigen::Vector3d p_a = (T_a_b * T_b_c) * Eigen::Vector3d::Zero();
  EXPECT_NEAR(p_a.x(), 1.0, 1e-12);
  EXPECT_NEAR(p_a.y(), 1.0, 1e-12);
  EXPECT_NEAR(p_a.z(), 0.0, 1e-12);
}

}  // namespace
}  // namespace mocap
