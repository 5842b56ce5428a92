#include "core/frame_graph.h"

#include <gtest/gtest.h>

#include "core/check.h"

namespace mocap {
namespace {

constexpr int64_t kMillisecond_ns = 1'000'000;

std::vector<PoseSample> Track(const Rigid3d& start, const Eigen::Vector3d& velocity_m_per_s) {
  std::vector<PoseSample> s;
  for (int i = 0; i <= 10; ++i) {
    const Rigid3d step = Rigid3d::FromRvec({0, 0, 0}, velocity_m_per_s * (i * 0.01));
    s.push_back({i * 10 * kMillisecond_ns, PoseStatus::kValid, step * start});
  }
  return s;
}

TEST(FrameGraph, ComposesTheLabellingChain) {
  // T_camera_mesh = inv(T_tracker_cambody * T_cambody_camera) * T_tracker_objbody * T_objbody_mesh.
  const Rigid3d T_tracker_cambody0 = Rigid3d::FromRvec({0.1, -0.2, 0.3}, {1, 2, 0.5});
  const Rigid3d T_tracker_objbody0 = Rigid3d::FromRvec({-0.3, 0.2, 0.1}, {1.5, 2.2, 0.1});
  const Rigid3d T_cambody_camera = Rigid3d::FromRvec({0.05, 0, 0}, {0.02, 0, 0.01});
  const Rigid3d T_objbody_mesh = Rigid3d::FromRvec({0, 0.4, 0}, {0, 0.03, 0});
  FrameGraph graph;
  graph.AddStream("tracker", "cambody", Track(T_tracker_cambody0, {0.1, 0, 0}));
  graph.AddStream("tracker", "objbody", Track(T_tracker_objbody0, {0, 0.2, 0}));
  graph.AddFixed("cambody", "camera", T_cambody_camera);
  graph.AddFixed("objbody", "mesh:bottle", T_objbody_mesh);

  const int64_t t = 35 * kMillisecond_ns;
  const FrameLookup lookup = graph.Lookup("camera", "mesh:bottle", t);
  ASSERT_TRUE(lookup.ok()) << lookup.reason;
  const Rigid3d T_tracker_cambody = Rigid3d::FromRvec({0, 0, 0}, {0.1 * 0.035, 0, 0}) * T_tracker_cambody0;
  const Rigid3d T_tracker_objbody = Rigid3d::FromRvec({0, 0, 0}, {0, 0.2 * 0.035, 0}) * T_tracker_objbody0;
  const Rigid3d expected = (T_tracker_cambody * T_cambody_camera).inverse() * T_tracker_objbody * T_objbody_mesh;
  EXPECT_LT(TranslationDistanceM(*lookup.T_a_b, expected), 1e-12);
  EXPECT_LT(RotationDistanceDeg(*lookup.T_a_b, expected), 1e-9);
  EXPECT_EQ(lookup.chain, (std::vector<std::string>{"camera", "cambody", "tracker", "objbody", "mesh:bottle"}));
  EXPECT_EQ(lookup.max_gap_ns, 10 * kMillisecond_ns);

  const FrameLookup back = graph.Lookup("mesh:bottle", "camera", t);
  ASSERT_TRUE(back.ok());
  EXPECT_LT(TranslationDistanceM(*back.T_a_b, expected.inverse()), 1e-12);
}

TEST(FrameGraph, ReportsWhyALookupFails) {
  FrameGraph graph;
  graph.AddStream("tracker", "objbody", Track(Rigid3d::Identity(), {0, 0, 0}));
  graph.AddFixed("cambody", "camera", Rigid3d::Identity());
  const FrameLookup none = graph.Lookup("camera", "objbody", 0);
  EXPECT_FALSE(none.ok());
  EXPECT_NE(none.reason.find("no chain"), std::string::npos);
  graph.AddStream("tracker", "cambody", Track(Rigid3d::Identity(), {0, 0, 0}));
  const FrameLookup late = graph.Lookup("camera", "objbody", 500 * kMillisecond_ns);
  EXPECT_FALSE(late.ok());
  EXPECT_EQ(late.failure, InterpolationFailure::kAfterEnd);
  EXPECT_THROW(graph.AddFixed("camera", "cambody", Rigid3d::Identity()), InputError);

  FrameGraph lost;
  auto samples = Track(Rigid3d::Identity(), {0, 0, 0});
  samples[3].status = PoseStatus::kOutOfVolume;
  lost.AddStream("tracker", "objbody", samples);
  const FrameLookup out_of_volume = lost.Lookup("tracker", "objbody", 25 * kMillisecond_ns);
  EXPECT_EQ(out_of_volume.failure, InterpolationFailure::kNeighbourInvalid);
  EXPECT_EQ(out_of_volume.neighbour_status, PoseStatus::kOutOfVolume);
}

}  // namespace
}  // namespace mocap
