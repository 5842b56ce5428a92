#include "label/pose_chain.h"

#include <algorithm>

#include "core/check.h"

namespace mocap {
namespace {

// Graph nodes are namespaced by kind so that user-chosen names cannot collide: a TUM import's camera body
// is called "camera", a Motive body may be called "tracker".
std::string BodyNode(const std::string& body) { return "body:" + body; }

std::string FlagOf(const FrameLookup& lookup) {
  switch (lookup.failure) {
    case InterpolationFailure::kGapTooLong: return "gap";
    case InterpolationFailure::kNeighbourInvalid:
      return lookup.neighbour_status == PoseStatus::kOutOfVolume ? "out_of_volume" : "missing_body";
    default: return "no_pose";
  }
}

}  // namespace

void PoseChainOptions::check() const {
  interpolation.check();
  if (speed_half_window_ns <= 0) throw InputError("PoseChainOptions", "speed_half_window_ns must be positive");
  if (!(fast_motion_m_per_s > 0) || !(fast_motion_deg_per_s > 0))
    throw InputError("PoseChainOptions", "fast-motion thresholds must be positive");
}

std::string PoseChain::WorldNode(const std::string& tracker_frame) const {
  if (tracker_frame == CameraNode()) return CameraNode();
  return "frame:" + tracker_frame;  // the tracker's frame, or another camera's frame (not linked to this one)
}

void PoseChain::AddBody(const PoseChainInput& input, const std::string& body) {
  if (std::find(added_bodies_.begin(), added_bodies_.end(), body) != added_bodies_.end()) return;
  const auto found = input.bodies.find(body);
  MOCAP_CHECK(found != input.bodies.end(), "body '", body, "' has no tracker");
  graph_.AddStream(WorldNode(found->second.tracker_frame), BodyNode(body), found->second.samples);
  added_bodies_.push_back(body);
}

PoseChainInput PoseChainInputOf(const SessionReader& session, const std::string& camera,
                                const std::vector<LabelObject>& objects, const LabelRig& rig) {
  PoseChainInput input;
  input.where = session.dir().string();
  const CameraStreamInfo* info = session.manifest().FindCamera(camera);
  if (info == nullptr) throw InputError(session.dir().string(), Str("the session has no camera '", camera, "'"));
  input.camera = *info;
  const LabelRigCamera* rig_camera = rig.Find(camera);
  std::vector<std::string> bodies = {rig_camera && rig_camera->body ? *rig_camera->body : info->camera_body};
  for (const LabelObject& object : objects)
    for (const BodyMount& mount : object.mounts) bodies.push_back(mount.body);
  for (const std::string& body : bodies) {
    const auto tracker = body.empty() ? std::nullopt : session.TrackerOfBody(body);
    if (!tracker || input.bodies.count(body)) continue;
    input.bodies[body] = {session.manifest().FindTracker(*tracker)->frame, session.PoseSamples(*tracker, body)};
  }
  return input;
}

PoseChain::PoseChain(const SessionReader& session, const std::string& camera, const std::vector<LabelObject>& objects,
                     const LabelRig& rig, const PoseChainOptions& options)
    : PoseChain(PoseChainInputOf(session, camera, objects, rig), objects, rig, options) {}

PoseChain::PoseChain(const PoseChainInput& input, const std::vector<LabelObject>& objects, const LabelRig& rig,
                     const PoseChainOptions& options)
    : camera_name_(input.camera.name), options_(options), latency_ns_(rig.tracker_latency_ns), graph_(options.interpolation) {
  options_.check();
  const CameraStreamInfo& info = input.camera;
  const LabelRigCamera* rig_camera = rig.Find(camera_name_);
  camera_ = rig_camera && rig_camera->color_camera ? *rig_camera->color_camera : info.color_camera;
  const std::string body = rig_camera && rig_camera->body ? *rig_camera->body : info.camera_body;
  if (!body.empty()) {
    if (!input.bodies.count(body))
      throw InputError(input.where, Str("camera body '", body, "' is reported by no tracker in the session"));
    AddBody(input, body);
    camera_world_ = WorldNode(input.bodies.at(body).tracker_frame);
    graph_.AddFixed(BodyNode(body), CameraNode(),
                    rig_camera && rig_camera->T_body_camera ? *rig_camera->T_body_camera : info.T_body_camera);
  }
  for (const LabelObject& object : objects) {
    for (const BodyMount& mount : object.mounts) {
      const std::string node = "mesh:" + object.name + "@" + mount.body;
      instances_.push_back({static_cast<uint16_t>(instances_.size() + 1), &object, &mount});
      mesh_nodes_.push_back(node);
      if (!input.bodies.count(mount.body)) {
        unreported_.push_back(Str("no tracker in the session reports body '", mount.body, "'"));
        continue;
      }
      unreported_.emplace_back();
      AddBody(input, mount.body);
      graph_.AddFixed(BodyNode(mount.body), node, mount.T_body_mesh);
    }
  }
}

InstancePose PoseChain::Lookup(size_t index, int64_t frame_stamp_ns) const {
  MOCAP_CHECK(index < instances_.size(), "instance ", index, " out of range");
  InstancePose out;
  if (!unreported_[index].empty()) {
    out.flags = {"missing_body"};
    out.reason = unreported_[index];
    return out;
  }
  const int64_t t = frame_stamp_ns + latency_ns_;
  const FrameLookup at = graph_.Lookup(CameraNode(), mesh_nodes_[index], t);
  if (!at.ok()) {
    out.flags = {FlagOf(at)};
    out.reason = at.reason;
    return out;
  }
  out.T_camera_mesh = at.T_a_b;
  out.interp_gap_ms = static_cast<double>(at.max_gap_ns) * 1e-6;
  const int64_t w = options_.speed_half_window_ns;
  const FrameLookup before = graph_.Lookup(CameraNode(), mesh_nodes_[index], t - w);
  const FrameLookup after = graph_.Lookup(CameraNode(), mesh_nodes_[index], t + w);
  if (before.ok() && after.ok()) {
    const double dt_s = 2.0 * static_cast<double>(w) * 1e-9;
    out.speed_m_per_s = TranslationDistanceM(*before.T_a_b, *after.T_a_b) / dt_s;
    out.speed_deg_per_s = RotationDistanceDeg(*before.T_a_b, *after.T_a_b) / dt_s;
    if (out.speed_m_per_s > options_.fast_motion_m_per_s || out.speed_deg_per_s > options_.fast_motion_deg_per_s)
      out.flags.push_back("fast_motion");
  }
  return out;
}

std::optional<Rigid3d> PoseChain::TrackerCameraPose(int64_t frame_stamp_ns) const {
  if (camera_world_.empty() || camera_world_ == CameraNode()) return std::nullopt;
  const FrameLookup at = graph_.Lookup(camera_world_, CameraNode(), frame_stamp_ns + latency_ns_);
  if (!at.ok()) return std::nullopt;
  return at.T_a_b;
}

}  // namespace mocap
