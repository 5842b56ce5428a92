#pragma once
// The chain of transforms from a session's camera to every object instance (DESIGN.md "Conventions"):
// T_camera_mesh = inv(T_tracker_cambody * T_cambody_camera) * T_tracker_objbody * T_objbody_mesh,
// interpolated at the frame time plus the rig's tracker latency. Sessions with known per-frame object
// poses (a tracker whose frame is "camera:<name>", e.g. a BOP import) link objects to the camera directly.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/frame_graph.h"
#include "label/label_objects.h"
#include "label/rig.h"
#include "session/reader.h"

namespace mocap {

struct PoseChainOptions {
  InterpolationOptions interpolation;
  /// Relative object-camera speed is measured over [t - w, t + w].
  int64_t speed_half_window_ns = 10'000'000;
  double fast_motion_m_per_s = 0.5;    ///< flag `fast_motion` above this relative speed
  double fast_motion_deg_per_s = 90.0;
  void check() const;
};

/// One object instance in the camera: an object on one of its tracker bodies.
struct LabelInstance {
  uint16_t instance_id = 0;  ///< 1-based, stable across frames (the label PNG value)
  const LabelObject* object = nullptr;
  const BodyMount* mount = nullptr;
};

struct InstancePose {
  std::optional<Rigid3d> T_camera_mesh;
  /// Why there is no pose or why it is doubtful: missing_body, out_of_volume, gap, no_pose, fast_motion.
  std::vector<std::string> flags;
  std::string reason;           ///< one line when T_camera_mesh is empty, or when a flag needs explaining
  double interp_gap_ms = 0;     ///< longest tracker gap bridged by interpolation along the chain
  double speed_m_per_s = -1;    ///< relative to the camera; -1 when it could not be measured
  double speed_deg_per_s = -1;
};

/// What a PoseChain reads of a recording: the camera's manifest entry and, for every tracked body, its
/// tracker's frame and its samples. A session on disk gives it (PoseChainInputOf); the capture daemon's
/// live view builds one from the samples it has just received, so its overlay is the labeller's chain.
struct PoseChainInput {
  std::string where;  ///< for messages (the session folder)
  CameraStreamInfo camera;
  struct Body {
    std::string tracker_frame;  ///< TrackerStreamInfo::frame of the tracker that reports it
    std::vector<PoseSample> samples;  ///< sorted by stamp_ns
  };
  std::map<std::string, Body> bodies;  ///< by body name; a body not here is reported by no tracker
};

/// The camera's entry and the samples of every body the rig's camera or the objects name. Throws
/// InputError when the camera is not in the session.
PoseChainInput PoseChainInputOf(const SessionReader& session, const std::string& camera,
                                const std::vector<LabelObject>& objects, const LabelRig& rig);

class PoseChain {
 public:
  /// Throws InputError when the camera is not in the session, or the camera body is named but not
  /// reported by any tracker in the session.
  PoseChain(const SessionReader& session, const std::string& camera, const std::vector<LabelObject>& objects,
            const LabelRig& rig, const PoseChainOptions& options = {});
  /// The same chain over samples held in memory. Throws InputError when the camera body is named but
  /// not in `input.bodies`.
  PoseChain(const PoseChainInput& input, const std::vector<LabelObject>& objects, const LabelRig& rig,
            const PoseChainOptions& options = {});

  const PinholeCamera& camera() const { return camera_; }
  const std::vector<LabelInstance>& instances() const { return instances_; }
  /// T_camera_mesh of instance `index` for the camera frame stamped `frame_stamp_ns`.
  InstancePose Lookup(size_t index, int64_t frame_stamp_ns) const;
  /// T_<tracker frame>_camera (colour optical frame) for the frame stamped `frame_stamp_ns`, through the
  /// same rig (mount, latency) as the labels; empty when the camera is not tracked or the lookup fails.
  std::optional<Rigid3d> TrackerCameraPose(int64_t frame_stamp_ns) const;

 private:
  std::string WorldNode(const std::string& tracker_frame) const;
  std::string CameraNode() const { return "camera:" + camera_name_; }
  void AddBody(const PoseChainInput& input, const std::string& body);

  std::string camera_name_;
  std::string camera_world_;  ///< the world node of the camera body's tracker ("" when not tracked)
  PinholeCamera camera_;
  PoseChainOptions options_;
  int64_t latency_ns_ = 0;
  FrameGraph graph_;
  std::vector<std::string> added_bodies_;
  std::vector<LabelInstance> instances_;
  std::vector<std::string> mesh_nodes_;
  std::vector<std::string> unreported_;  ///< per instance: why its body cannot be looked up ("" if it can)
};

}  // namespace mocap
