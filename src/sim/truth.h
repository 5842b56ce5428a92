#pragma once
// Ground truth of a simulated recording, kept beside the session (S/truth/) so every stage can be
// scored: the true calibration, the calibration handed to the labeller (truth + injected errors), and
// per frame the true camera and object poses. The tracker streams of the simulated rig come from here
// too, so they and the truth share one motion.
#include <cstdint>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/rigid3.h"
#include "sim/scene_motion.h"
#include "sim/tracker_model.h"

namespace mocap::sim {

/// A rig calibration: what the labeller needs to compose T_camera_mesh from tracker samples.
struct RigCalibration {
  Rigid3d T_cambody_camera;             ///< camera mount
  std::vector<std::string> objects;     ///< object names, parallel to T_objbody_mesh
  std::vector<Rigid3d> T_objbody_mesh;  ///< object mounts
  /// Tracker-to-camera latency: a tracker sample stamped t on the host was measured at t - latency,
  /// and a camera frame stamped t was exposed at t - camera_delay; this is their difference (ns).
  int64_t tracker_latency_ns = 0;
  PinholeCamera color_camera;
  PinholeCamera depth_camera;           ///< equals color_camera for registered Kinect v1 depth
  Rigid3d T_color_depth;                ///< depth optical frame in the colour optical frame
};

struct ObjectTruth {
  std::string name;
  int id = 0;
  Rigid3d T_camera_mesh;      ///< at the depth exposure
  Rigid3d T_color_mesh;       ///< at the colour exposure (differs from depth for Kinect v2)
  double speed_mps = 0;       ///< of the mesh origin, world
  double angular_speed_degps = 0;
};

struct OccluderTruth {
  std::string name;
  Rigid3d T_camera_occluder;  ///< at the depth exposure
};

struct FrameTruth {
  int index = 0;
  int64_t depth_time_ns = 0;  ///< exposure time of the depth frame (scenario time, host clock)
  int64_t color_time_ns = 0;  ///< exposure time of the colour frame
  Rigid3d T_world_camera;     ///< colour optical frame at the depth exposure
  Rigid3d T_world_color;      ///< colour optical frame at the colour exposure
  std::vector<ObjectTruth> objects;
  std::vector<OccluderTruth> occluders;
};

struct SimulationTruth {
  RigCalibration true_calibration;
  RigCalibration given_calibration;  ///< true_calibration with the scenario's errors applied
  CalibrationErrors injected;
  Rigid3d T_world_tracker;
  std::vector<FrameTruth> frames;
};

/// Nanoseconds of scenario time (the host clock of a simulated session).
int64_t NsFromSeconds(double t_s);

/// The true calibration of the scenario's rig.
RigCalibration TrueCalibration(const Scenario& scenario, const SimObjects& library);
/// `truth` with `errors` applied: mount errors compose on the body side (T_body_x * error), latency adds,
/// the focal length scales and the principal point shifts (colour and depth camera alike).
RigCalibration ApplyCalibrationErrors(const RigCalibration& truth, const CalibrationErrors& errors);

/// Per-frame truth of the whole scenario. Precondition: scenario.check(library) passed.
SimulationTruth ComputeTruth(const SceneMotion& motion, const SimObjects& library);

/// Tracker streams of every body (the camera tool first, then each object in scenario order), sampled
/// at the tracker rate over the recording plus half a second either side, stamped on the host clock.
std::vector<BodyStream> SimulateTrackerStreams(const SceneMotion& motion, const SimObjects& library);

}  // namespace mocap::sim
