#pragma once
// A simulated recording: which objects stand where and how they move, how the camera moves, how the
// tracker and the depth sensor behave, and which calibration errors are handed to the labeller. The YAML
// form (docs/simulation.md) maps onto these structs in src/cli/scenario_yaml.cc; DefaultScenario() is
// the embedded scene that `mocaplabel demo` runs (scenarios/default.yaml holds the same).
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/rigid3.h"
#include "sim/kinect1_model.h"
#include "sim/kinect2_model.h"
#include "sim/sim_objects.h"
#include "sim/tracker_options.h"

namespace mocap::sim {

/// A pose at a time. Between keyframes the motion is a minimum-jerk blend (zero velocity and
/// acceleration at every keyframe), so a motion pauses at each keyframe.
struct PoseKeyframe {
  double t_s = 0;
  Rigid3d pose;  ///< T_world_<thing>
};

struct ScenarioObject {
  std::string name;  ///< an object of the library (objects.yaml)
  std::vector<PoseKeyframe> motion;  ///< T_world_mesh keyframes; one keyframe = static
  double depth_loss = 0;  ///< fraction of its surface without depth (dark or shiny; sim/depth_loss.h)
};

/// Something rendered and blocking lines of sight that is not labelled (a hand).
struct ScenarioOccluder {
  std::string name;
  std::string mesh;  ///< mesh file in the object library folder
  /// Box around the occluder in its own frame, used for the tracker's line-of-sight test.
  Eigen::Vector3d box_center_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d box_half_extents_m{0.09, 0.065, 0.02};
  std::vector<PoseKeyframe> motion;  ///< T_world_occluder keyframes
  double depth_loss = 0;  ///< fraction of its surface without depth (a dark glove; sim/depth_loss.h)
};

/// Pan/tilt of a robot head (PR2-like): T_world_camera = T_world_head * Rz(pan) * Ry(tilt) * T_tilt_camera.
struct PanTiltKeyframe {
  double t_s = 0;
  double pan_deg = 0;   ///< about the head's z (up) axis, positive to the left
  double tilt_deg = 0;  ///< about the head's y axis after panning, positive looks down
};

struct CameraMotion {
  enum class Type { kRobotHead, kHandheld } type = Type::kRobotHead;
  Rigid3d T_world_head;            ///< robot head base (x forward, z up)
  Rigid3d T_tilt_camera;           ///< camera optical frame in the tilt link
  std::vector<PanTiltKeyframe> pan_tilt;
  std::vector<PoseKeyframe> handheld;  ///< T_world_camera keyframes (kHandheld)
  double handheld_shake_mm = 0;    ///< RMS of a smooth hand tremor added to handheld motion
  double handheld_shake_deg = 0;
};

/// Errors in the calibration handed to the labeller (the truth is unchanged).
struct CalibrationErrors {
  Eigen::Vector3d camera_mount_translation_m = Eigen::Vector3d::Zero();  ///< added in the camera body frame
  Eigen::Vector3d camera_mount_rotation_deg = Eigen::Vector3d::Zero();   ///< rotation vector, degrees
  struct ObjectMount {
    std::string object;
    Eigen::Vector3d translation_m = Eigen::Vector3d::Zero();
    Eigen::Vector3d rotation_deg = Eigen::Vector3d::Zero();
  };
  std::vector<ObjectMount> object_mounts;
  double latency_ms = 0;       ///< added to the true tracker-to-camera latency
  double focal_scale = 0;      ///< relative error of fx and fy (0.01 = 1 % too long)
  Eigen::Vector2d principal_point_px = Eigen::Vector2d::Zero();  ///< added to (cx, cy)
  bool any() const;
};

enum class SensorKind { kKinect1, kKinect2 };
std::string_view ToString(SensorKind kind);
/// Throws InputError for anything but "kinect1" / "kinect2".
SensorKind SensorKindFromString(std::string_view name, const std::string& where);

struct ScenarioOptions {
  std::string name = "default";
  double frame_rate_hz = 30.0;  ///< depth frame rate
  int frame_count = 300;
  double start_s = 0.0;         ///< scenario time of the first depth frame
  uint64_t seed = 1;
  SensorKind sensor = SensorKind::kKinect1;
  Kinect1Options kinect1;
  Kinect2Options kinect2;
  TrackerOptions tracker;
  CalibrationErrors errors;
  /// Throws InputError naming the offending field.
  void check() const;
  double duration_s() const { return frame_count / frame_rate_hz; }
};

struct Scenario {
  ScenarioOptions options;
  std::vector<ScenarioObject> objects;
  std::vector<ScenarioOccluder> occluders;
  CameraMotion camera;
  MarkerBody camera_body;          ///< the marker tool on the camera
  Rigid3d T_cambody_camera;        ///< true camera mount
  /// Throws InputError naming `where` and the offending entry (times not increasing, empty motions,
  /// unknown objects in `library`, errors naming objects not in the scene).
  void check(const SimObjects& library, const std::string& where) const;
};

/// The embedded default: ~300 frames at 30 Hz, the oil bottle, funnel and engine block on a table,
/// the bottle picked up, carried, put down and briefly hidden by a hand, the camera on a panning and
/// tilting robot head, a Kinect1 and a Polaris-Vega-like tracker at 60 Hz.
Scenario DefaultScenario();

/// T_world_x for a frame at `position` whose `forward_axis` (+z for a camera, -z for an NDI tracker)
/// points at `target`, with `up` (world) as close to the frame's -y (camera) as possible.
Rigid3d LookAt(const Eigen::Vector3d& position, const Eigen::Vector3d& target, const Eigen::Vector3d& up,
               bool forward_is_minus_z = false);

/// Pose from a position and roll/pitch/yaw (degrees, R = Rz(yaw) * Ry(pitch) * Rx(roll)).
Rigid3d PoseXyzRpy(const Eigen::Vector3d& xyz_m, const Eigen::Vector3d& rpy_deg);

}  // namespace mocap::sim
