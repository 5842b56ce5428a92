#include <gtest/gtest.h>

#include "core/check.h"
#include "sim/scene_motion.h"
#include "sim/truth.h"

namespace mocap::sim {
namespace {

TEST(MinimumJerk, EndpointsAndRates) {
  EXPECT_DOUBLE_EQ(MinimumJerk(0.0), 0.0);
  EXPECT_DOUBLE_EQ(MinimumJerk(1.0), 1.0);
  EXPECT_DOUBLE_EQ(MinimumJerk(0.5), 0.5);
  EXPECT_DOUBLE_EQ(MinimumJerkRate(0.0), 0.0);
  EXPECT_DOUBLE_EQ(MinimumJerkRate(1.0), 0.0);
  EXPECT_DOUBLE_EQ(MinimumJerkRate(0.5), 1.875);  // peak velocity 15/8 of the mean
  const double h = 1e-6;
  EXPECT_NEAR((MinimumJerk(0.3 + h) - MinimumJerk(0.3 - h)) / (2 * h), MinimumJerkRate(0.3), 1e-6);
}

TEST(Keyframes, HoldOutsideAndBlendInside) {
  const std::vector<PoseKeyframe> keys{{1.0, PoseXyzRpy({0, 0, 0}, {0, 0, 0})}, {3.0, PoseXyzRpy({1, 0, 0}, {0, 0, 90})}};
  EXPECT_NEAR(EvaluateKeyframes(keys, 0.0).translation().x(), 0.0, 1e-12);
  EXPECT_NEAR(EvaluateKeyframes(keys, 5.0).translation().x(), 1.0, 1e-12);
  const Rigid3d mid = EvaluateKeyframes(keys, 2.0);
  EXPECT_NEAR(mid.translation().x(), 0.5, 1e-12);
  EXPECT_NEAR(RotationDistanceDeg(mid, Rigid3d()), 45.0, 1e-9);
}

TEST(SceneMotion, MotionIsContinuouslyDifferentiable) {
  // Velocity just before and just after every keyframe of the carried bottle agree (C1) and vanish at it.
  const Scenario scenario = DefaultScenario();
  const SceneMotion motion(scenario);
  const size_t bottle = 3;
  ASSERT_EQ(scenario.objects[bottle].name, "oil_bottle");
  for (const PoseKeyframe& key : scenario.objects[bottle].motion) {
    const Twist before = motion.ObjectTwist(bottle, key.t_s - 0.01), after = motion.ObjectTwist(bottle, key.t_s + 0.01);
    EXPECT_LT(before.linear_mps.norm(), 0.01) << key.t_s;
    EXPECT_LT(after.linear_mps.norm(), 0.01) << key.t_s;
  }
  // Carry: 0.28 m in 2.4 s; minimum jerk peaks at 15/8 of the mean speed.
  const Twist mid = motion.ObjectTwist(bottle, 3.8);
  const double distance = (scenario.objects[bottle].motion[3].pose.translation() - scenario.objects[bottle].motion[2].pose.translation()).norm();
  EXPECT_NEAR(mid.linear_mps.norm(), 1.875 * distance / 2.4, 1e-3);
  EXPECT_NEAR(mid.angular_degps.norm(), 1.875 * 40.0 / 2.4, 0.05);
}

TEST(SceneMotion, RobotHeadPansAndTilts) {
  const Scenario scenario = DefaultScenario();
  const SceneMotion motion(scenario);
  // At a keyframe the optical axis points at the keyframe's pan and tilt.
  for (const PanTiltKeyframe& key : scenario.camera.pan_tilt) {
    const Eigen::Vector3d axis = motion.T_world_camera(key.t_s).rotation() * Eigen::Vector3d::UnitZ();
    EXPECT_NEAR(DegFromRad(std::atan2(axis.y(), axis.x())), key.pan_deg, 1e-6);
    EXPECT_NEAR(DegFromRad(std::asin(-axis.z())), key.tilt_deg, 1e-6);
  }
}

TEST(Scenario, DefaultIsValidAndLasts300Frames) {
  const Scenario scenario = DefaultScenario();
  EXPECT_NO_THROW(scenario.check(DefaultSimObjects(), "default"));
  EXPECT_EQ(scenario.options.frame_count, 300);
  EXPECT_DOUBLE_EQ(scenario.options.duration_s(), 10.0);
}

TEST(Scenario, CheckNamesTheOffendingEntry) {
  const SimObjects library = DefaultSimObjects();
  Scenario unknown = DefaultScenario();
  unknown.objects[0].name = "spanner";
  try {
    unknown.check(library, "scene.yaml");
    FAIL() << "unknown object accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("spanner"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("objects[0]"), std::string::npos);
  }
  Scenario backwards = DefaultScenario();
  backwards.objects[3].motion[2].t_s = 1.0;
  EXPECT_THROW(backwards.check(library, "scene.yaml"), InputError);
  Scenario bad_rate = DefaultScenario();
  bad_rate.options.tracker.rate_hz = 0;
  EXPECT_THROW(bad_rate.check(library, "scene.yaml"), InputError);
  Scenario bad_error = DefaultScenario();
  bad_error.options.errors.object_mounts.push_back({"wrench", {0.001, 0, 0}, {0, 0, 0}});
  EXPECT_THROW(bad_error.check(library, "scene.yaml"), InputError);
}

TEST(Truth, ComposesTheDesignChainExactly) {
  // T_camera_mesh = inv(T_tracker_cambody * T_cambody_camera) * T_tracker_objbody * T_objbody_mesh with
  // noise-free tracker poses reproduces the truth (DESIGN.md "Conventions").
  const Scenario scenario = DefaultScenario();
  const SimObjects library = DefaultSimObjects();
  const SceneMotion motion(scenario);
  const SimulationTruth truth = ComputeTruth(motion, library);
  ASSERT_EQ(truth.frames.size(), 300u);
  const Rigid3d T_tracker_world = scenario.options.tracker.T_world_tracker.inverse();
  for (int f : {0, 75, 150, 299}) {
    const double t = f / 30.0;
    const Rigid3d T_tracker_cambody = T_tracker_world * motion.T_world_camera(t) * scenario.T_cambody_camera.inverse();
    for (size_t i = 0; i < scenario.objects.size(); ++i) {
      const Rigid3d& T_objbody_mesh = truth.true_calibration.T_objbody_mesh[i];
      const Rigid3d T_tracker_objbody = T_tracker_world * motion.T_world_mesh(i, t) * T_objbody_mesh.inverse();
      const Rigid3d composed = (T_tracker_cambody * truth.true_calibration.T_cambody_camera).inverse() * T_tracker_objbody * T_objbody_mesh;
      EXPECT_LT(TranslationDistanceM(composed, truth.frames[f].objects[i].T_camera_mesh), 1e-9);
      EXPECT_LT(RotationDistanceDeg(composed, truth.frames[f].objects[i].T_camera_mesh), 1e-6);
    }
  }
}

TEST(Truth, ErrorsChangeOnlyTheGivenCalibration) {
  Scenario scenario = DefaultScenario();
  scenario.options.errors.camera_mount_translation_m = {0.005, 0, 0};
  scenario.options.errors.latency_ms = 20;
  scenario.options.errors.focal_scale = 0.01;
  scenario.options.errors.object_mounts.push_back({"funnel", {0, 0.002, 0}, {0, 0, 1}});
  const SimulationTruth truth = ComputeTruth(SceneMotion(scenario), DefaultSimObjects());
  const SimulationTruth clean = ComputeTruth(SceneMotion(DefaultScenario()), DefaultSimObjects());
  EXPECT_NEAR(TranslationDistanceM(truth.given_calibration.T_cambody_camera, truth.true_calibration.T_cambody_camera), 0.005, 1e-12);
  EXPECT_EQ(truth.given_calibration.tracker_latency_ns - truth.true_calibration.tracker_latency_ns, 20'000'000);
  EXPECT_NEAR(truth.given_calibration.color_camera.fx, 1.01 * truth.true_calibration.color_camera.fx, 1e-9);
  EXPECT_NEAR(RotationDistanceDeg(truth.given_calibration.T_objbody_mesh[2], truth.true_calibration.T_objbody_mesh[2]), 1.0, 1e-9);
  EXPECT_LT(TranslationDistanceM(truth.frames[120].objects[3].T_camera_mesh, clean.frames[120].objects[3].T_camera_mesh), 1e-12);
}

TEST(Truth, Kinect2ColourLagsDepth) {
  Scenario scenario = DefaultScenario();
  scenario.options.sensor = SensorKind::kKinect2;
  const SimulationTruth truth = ComputeTruth(SceneMotion(scenario), DefaultSimObjects());
  double sum_ms = 0;
  for (const FrameTruth& frame : truth.frames) sum_ms += (frame.color_time_ns - frame.depth_time_ns) * 1e-6;
  EXPECT_NEAR(sum_ms / truth.frames.size(), scenario.options.kinect2.colour_delay_ms, 1.0);
  // While the bottle is carried, the pose seen by the colour camera is the one of speed * delay later.
  const FrameTruth& frame = truth.frames[114];
  const ObjectTruth& bottle = frame.objects[3];
  EXPECT_GT(bottle.speed_mps, 0.1);
  const Rigid3d world_at_depth = frame.T_world_camera * truth.true_calibration.T_color_depth * bottle.T_camera_mesh;
  const Rigid3d world_at_color = frame.T_world_color * bottle.T_color_mesh;
  const double delay_s = (frame.color_time_ns - frame.depth_time_ns) * 1e-9;
  EXPECT_NEAR(TranslationDistanceM(world_at_depth, world_at_color), bottle.speed_mps * std::abs(delay_s),
              0.05 * bottle.speed_mps * std::abs(delay_s));
}

}  // namespace
}  // namespace mocap::sim
