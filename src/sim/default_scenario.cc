// The embedded default scene (scenarios/default.yaml holds the same, checked by a test).
#include "sim/scenario.h"

namespace mocap::sim {
namespace {

constexpr double kTableTopZ = 0.75;

std::vector<PoseKeyframe> Static(const Rigid3d& pose) { return {{0.0, pose}}; }

std::vector<PoseKeyframe> BottleMotion() {
  // Placed, picked up (t = 2.0 s), lifted 12 cm, carried and turned 40 degrees, put down (5.6 s).
  return {{0.0, PoseXyzRpy({-0.25, -0.15, kTableTopZ}, {0, 0, 0})},
          {2.0, PoseXyzRpy({-0.25, -0.15, kTableTopZ}, {0, 0, 0})},
          {2.6, PoseXyzRpy({-0.25, -0.15, kTableTopZ + 0.12}, {0, 0, 0})},
          {5.0, PoseXyzRpy({0.0, -0.27, kTableTopZ + 0.12}, {0, 0, 40})},
          {5.6, PoseXyzRpy({0.0, -0.27, kTableTopZ}, {0, 0, 40})}};
}

std::vector<PoseKeyframe> HandMotion() {
  // The hand comes in, holds the handle while the bottle is carried, lets go, hovers over the bottle's
  // marker tool (hiding it from the tracker, 6.8-7.2 s), passes in front of the bottle (hiding it from
  // the camera, 7.7-8.2 s) and leaves.
  const Rigid3d grasp_in_bottle = PoseXyzRpy({-0.13, 0.0, 0.18}, {90, 0, 0});
  std::vector<PoseKeyframe> motion{{0.0, PoseXyzRpy({-0.3, -0.9, 1.0}, {90, 0, 0})}};
  for (const PoseKeyframe& k : BottleMotion()) {
    if (k.t_s < 2.0) continue;
    motion.push_back({k.t_s, k.pose * grasp_in_bottle});
  }
  motion.insert(motion.begin() + 1, {1.3, BottleMotion()[1].pose * PoseXyzRpy({-0.18, 0.0, 0.20}, {90, 0, 0})});
  motion.push_back({6.3, PoseXyzRpy({-0.45, -0.20, 1.00}, {90, 0, 0})});
  motion.push_back({6.8, PoseXyzRpy({-0.06, -0.17, 1.00}, {0, 0, 0})});
  motion.push_back({7.2, PoseXyzRpy({-0.06, -0.17, 1.00}, {0, 0, 0})});
  motion.push_back({7.7, PoseXyzRpy({-0.25, -0.25, 0.90}, {90, 0, 10})});
  motion.push_back({8.2, PoseXyzRpy({-0.25, -0.23, 0.91}, {90, 0, 10})});
  motion.push_back({9.0, PoseXyzRpy({-0.30, -0.90, 1.10}, {90, 0, 0})});
  return motion;
}

CameraMotion RobotHead() {
  CameraMotion camera;
  camera.type = CameraMotion::Type::kRobotHead;
  camera.T_world_head = PoseXyzRpy({-0.9, 0.0, 1.30}, {0, 0, 0});
  // Optical frame (z forward, x right, y down) in the tilt link (x forward, z up), 5 cm ahead of and
  // 8 cm above the tilt axis.
  Eigen::Matrix3d R;
  R << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  camera.T_tilt_camera = Rigid3d(R, Eigen::Vector3d(0.05, 0.0, 0.08));
  camera.pan_tilt = {{0.0, 6, 30}, {3.0, -3, 34}, {6.0, -8, 31}, {8.5, 2, 35}, {10.0, 0, 32}};
  return camera;
}

}  // namespace

Scenario DefaultScenario() {
  Scenario scenario;
  scenario.options.name = "default";
  scenario.options.frame_rate_hz = 30.0;
  scenario.options.frame_count = 300;
  scenario.options.seed = 20170529;
  scenario.options.sensor = SensorKind::kKinect1;
  scenario.options.tracker.T_world_tracker = LookAt({-0.32, 1.25, 2.55}, {-0.32, 0.0, 0.95}, Eigen::Vector3d::UnitZ(), true);
  scenario.objects = {
      {"table", Static(Rigid3d())},
      {"engine_block", Static(PoseXyzRpy({0.25, 0.10, kTableTopZ}, {0, 0, 90}))},
      {"funnel", Static(PoseXyzRpy({-0.05, 0.25, kTableTopZ + 0.15}, {180, 0, 90}))},
      {"oil_bottle", BottleMotion()},
  };
  ScenarioOccluder hand;
  hand.name = "hand";
  hand.mesh = "hand.ply";
  hand.box_center_m = {0.035, 0.0, 0.0};
  hand.box_half_extents_m = {0.09, 0.065, 0.02};
  hand.motion = HandMotion();
  scenario.occluders = {hand};
  scenario.camera = RobotHead();
  scenario.camera_body = DefaultCameraBody();
  scenario.T_cambody_camera = DefaultCameraMount();
  return scenario;
}

}  // namespace mocap::sim
