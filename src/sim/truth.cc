#include "sim/truth.h"

#include <cmath>

#include "core/check.h"
#include "sim/kinect1_model.h"
#include "sim/kinect2_model.h"

namespace mocap::sim {
namespace {

Rigid3d ErrorTransform(const Eigen::Vector3d& translation_m, const Eigen::Vector3d& rotation_deg) {
  return Rigid3d::FromRvec(rotation_deg * (M_PI / 180.0), translation_m);
}

PinholeCamera PerturbIntrinsics(PinholeCamera camera, const CalibrationErrors& errors) {
  camera.fx *= 1.0 + errors.focal_scale;
  camera.fy *= 1.0 + errors.focal_scale;
  camera.cx += errors.principal_point_px.x();
  camera.cy += errors.principal_point_px.y();
  return camera;
}

std::vector<OccluderBox> OccludersInTracker(const SceneMotion& motion, const Rigid3d& T_tracker_world, double t_s) {
  std::vector<OccluderBox> boxes;
  const Scenario& scenario = motion.scenario();
  for (size_t i = 0; i < scenario.occluders.size(); ++i) {
    const ScenarioOccluder& occluder = scenario.occluders[i];
    const Rigid3d T_occluder_box(Eigen::Quaterniond::Identity(), occluder.box_center_m);
    boxes.push_back({T_tracker_world * motion.T_world_occluder(i, t_s) * T_occluder_box, occluder.box_half_extents_m});
  }
  return boxes;
}

}  // namespace

int64_t NsFromSeconds(double t_s) { return std::llround(t_s * 1e9); }

RigCalibration TrueCalibration(const Scenario& scenario, const SimObjects& library) {
  RigCalibration calibration;
  calibration.T_cambody_camera = scenario.T_cambody_camera;
  for (const ScenarioObject& object : scenario.objects) {
    const SimObject* spec = library.Find(object.name);
    MOCAP_CHECK(spec != nullptr, "object ", object.name, " missing from the library (scenario not checked?)");
    calibration.objects.push_back(object.name);
    calibration.T_objbody_mesh.push_back(spec->T_body_mesh);
  }
  calibration.tracker_latency_ns = NsFromSeconds(scenario.options.tracker.latency_ms * 1e-3);
  if (scenario.options.sensor == SensorKind::kKinect1) {
    calibration.color_camera = calibration.depth_camera = Kinect1ColorCamera();
  } else {
    calibration.color_camera = Kinect2ColorCamera();
    calibration.depth_camera = Kinect2DepthCamera();
    calibration.T_color_depth = Kinect2TColorDepth();
  }
  return calibration;
}

RigCalibration ApplyCalibrationErrors(const RigCalibration& truth, const CalibrationErrors& errors) {
  RigCalibration given = truth;
  given.T_cambody_camera = truth.T_cambody_camera * ErrorTransform(errors.camera_mount_translation_m, errors.camera_mount_rotation_deg);
  for (const auto& mount : errors.object_mounts) {
    for (size_t i = 0; i < given.objects.size(); ++i)
      if (given.objects[i] == mount.object)
        given.T_objbody_mesh[i] = truth.T_objbody_mesh[i] * ErrorTransform(mount.translation_m, mount.rotation_deg);
  }
  given.tracker_latency_ns = truth.tracker_latency_ns + NsFromSeconds(errors.latency_ms * 1e-3);
  given.color_camera = PerturbIntrinsics(truth.color_camera, errors);
  given.depth_camera = PerturbIntrinsics(truth.depth_camera, errors);
  return given;
}

SimulationTruth ComputeTruth(const SceneMotion& motion, const SimObjects& library) {
  const Scenario& scenario = motion.scenario();
  SimulationTruth truth;
  truth.true_calibration = TrueCalibration(scenario, library);
  truth.given_calibration = ApplyCalibrationErrors(truth.true_calibration, scenario.options.errors);
  truth.injected = scenario.options.errors;
  truth.T_world_tracker = scenario.options.tracker.T_world_tracker;
  const Rigid3d T_color_depth = truth.true_calibration.T_color_depth;
  for (int f = 0; f < scenario.options.frame_count; ++f) {
    FrameTruth frame;
    frame.index = f;
    const double t_depth = scenario.options.start_s + f / scenario.options.frame_rate_hz;
    frame.depth_time_ns = NsFromSeconds(t_depth);
    frame.color_time_ns = scenario.options.sensor == SensorKind::kKinect2
                              ? Kinect2ColorTimeNs(frame.depth_time_ns, f, scenario.options.kinect2, scenario.options.seed)
                              : frame.depth_time_ns;
    const double t_color = frame.color_time_ns * 1e-9;
    frame.T_world_camera = motion.T_world_camera(t_depth);
    frame.T_world_color = motion.T_world_camera(t_color);
    // Depth optical frame at the depth exposure; colour optical frame at the colour exposure.
    const Rigid3d T_depth_world = (frame.T_world_camera * T_color_depth).inverse();
    const Rigid3d T_color_world = frame.T_world_color.inverse();
    for (size_t i = 0; i < scenario.objects.size(); ++i) {
      ObjectTruth object;
      object.name = scenario.objects[i].name;
      object.id = library.Find(object.name)->id;
      object.T_camera_mesh = T_depth_world * motion.T_world_mesh(i, t_depth);
      object.T_color_mesh = T_color_world * motion.T_world_mesh(i, t_color);
      const Twist twist = motion.ObjectTwist(i, t_depth);
      object.speed_mps = twist.linear_mps.norm();
      object.angular_speed_degps = twist.angular_degps.norm();
      frame.objects.push_back(object);
    }
    for (size_t i = 0; i < scenario.occluders.size(); ++i)
      frame.occluders.push_back({scenario.occluders[i].name, T_depth_world * motion.T_world_occluder(i, t_depth)});
    truth.frames.push_back(std::move(frame));
  }
  return truth;
}

std::vector<BodyStream> SimulateTrackerStreams(const SceneMotion& motion, const SimObjects& library) {
  const Scenario& scenario = motion.scenario();
  const TrackerOptions& tracker = scenario.options.tracker;
  const Rigid3d T_tracker_world = tracker.T_world_tracker.inverse();
  std::vector<BodyStream> streams;
  std::vector<const MarkerBody*> bodies{&scenario.camera_body};
  for (const ScenarioObject& object : scenario.objects) bodies.push_back(&library.Find(object.name)->body);
  auto T_world_body = [&](size_t body, double t) {
    if (body == 0) return motion.T_world_camera(t) * scenario.T_cambody_camera.inverse();
    return motion.T_world_mesh(body - 1, t) * library.Find(scenario.objects[body - 1].name)->T_body_mesh.inverse();
  };
  const double t_begin = scenario.options.start_s - 0.5, t_end = scenario.options.start_s + scenario.options.duration_s() + 0.5;
  const auto first = static_cast<int64_t>(std::ceil(t_begin * tracker.rate_hz));
  const auto last = static_cast<int64_t>(std::floor(t_end * tracker.rate_hz));
  const int64_t latency_ns = NsFromSeconds(tracker.latency_ms * 1e-3);
  for (size_t b = 0; b < bodies.size(); ++b) {
    BodyStream stream;
    stream.body = bodies[b]->name;
    Rng rng = Rng::Derive(scenario.options.seed, 1000 + b);
    for (int64_t k = first; k <= last; ++k) {
      const double t = static_cast<double>(k) / tracker.rate_hz;
      const Rigid3d T_tracker_body = T_tracker_world * T_world_body(b, t);
      const std::vector<OccluderBox> occluders = OccludersInTracker(motion, T_tracker_world, t);
      const TrackerMeasurement m = MeasureBody(*bodies[b], T_tracker_body, occluders, tracker, rng);
      stream.samples.push_back({NsFromSeconds(t) + latency_ns, m.status, HasPose(m.status) ? m.T_tracker_body : Rigid3d()});
      stream.measurements.push_back(m);
      stream.true_T_tracker_body.push_back(T_tracker_body);
    }
    streams.push_back(std::move(stream));
  }
  return streams;
}

}  // namespace mocap::sim
