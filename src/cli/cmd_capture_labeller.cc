#include "cli/cmd_capture_labeller.h"

#include <algorithm>

#include "core/check.h"
#include "label/labeller.h"

namespace mocap::cli {

namespace {

// The daemon's recent samples as a PoseChain reads a session: every body its trackers list (a body
// without samples yet is there, empty, so its instances say why they have no pose), samples by stamp.
PoseChainInput LiveChainInput(const SessionManifest& manifest, const CameraStreamInfo& camera,
                              const std::map<std::string, std::vector<TrackerRecord>>& samples) {
  PoseChainInput input{"live camera " + camera.name, camera, {}};
  for (const TrackerStreamInfo& tracker : manifest.trackers)
    for (const std::string& body : tracker.bodies) input.bodies[body].tracker_frame = tracker.frame;
  for (const auto& [tracker, records] : samples) {
    const TrackerStreamInfo* info = manifest.FindTracker(tracker);
    if (info == nullptr) continue;
    for (const TrackerRecord& r : records) {
      PoseChainInput::Body& body = input.bodies[r.body];
      body.tracker_frame = info->frame;
      body.samples.push_back({r.stamp_ns, r.status, r.T_frame_body});
    }
  }
  for (auto& [name, body] : input.bodies)
    std::stable_sort(body.samples.begin(), body.samples.end(),
                     [](const PoseSample& a, const PoseSample& b) { return a.stamp_ns < b.stamp_ns; });
  return input;
}

std::string Join(const std::vector<std::string>& flags) {
  std::string out;
  for (const std::string& f : flags) out += (out.empty() ? "" : ", ") + f;
  return out;
}

}  // namespace

RigFrameLabeller::RigFrameLabeller(LabelRig rig, std::vector<LabelObject> objects)
    : rig_(std::move(rig)), objects_(std::move(objects)) {
  const LabelOptions defaults;  // the same chain and renderer settings as `mocaplabel label`
  chain_options_ = defaults.chain;
  renderer_options_ = defaults.renderer;
  rig_.check("rig");
  CheckLabelObjects(objects_, "objects");
  for (const LabelObject& o : objects_) meshes_.push_back(LoadMesh(o.mesh_path.string(), o.unit_scale_to_m));
}

RigFrameLabeller::~RigFrameLabeller() = default;

void RigFrameLabeller::EnsureRenderer() {
  if (renderer_) return;
  context_ = RenderContext::Create();
  context_->MakeCurrent();
  renderer_ = std::make_unique<Renderer>(*context_, renderer_options_);
  for (size_t i = 0; i < meshes_.size(); ++i)
    handles_.push_back(renderer_->Upload(meshes_[i], objects_[i].back_face_culling.value_or(renderer_options_.back_face_culling)));
}

void RigFrameLabeller::ThreadEnd() {
  renderer_.reset();
  context_.reset();
  handles_.clear();
}

std::optional<capture::FrameLabels> RigFrameLabeller::Label(const SessionManifest& manifest, const std::string& camera,
                                                            const CameraFrameRecord& frame,
                                                            const std::map<std::string, std::vector<TrackerRecord>>& samples) {
  const CameraStreamInfo* info = manifest.FindCamera(camera);
  if (info == nullptr) return std::nullopt;
  const PoseChain chain(LiveChainInput(manifest, *info, samples), objects_, rig_, chain_options_);
  EnsureRenderer();
  capture::FrameLabels labels;
  std::vector<RenderItem> items;
  for (size_t i = 0; i < chain.instances().size(); ++i) {
    const LabelInstance& instance = chain.instances()[i];
    const InstancePose pose = chain.Lookup(i, frame.stamp_ns);
    const auto object_index = static_cast<size_t>(instance.object - objects_.data());
    if (pose.T_camera_mesh) items.push_back({handles_[object_index], *pose.T_camera_mesh, instance.instance_id});
    labels.instances.push_back({instance.instance_id, instance.object->name, instance.mount->body,
                                pose.T_camera_mesh.has_value(), pose.reason.empty() ? Join(pose.flags) : pose.reason});
  }
  const RenderOutput render = renderer_->Render(chain.camera(), items);
  const LabelImage& ids = render.instance_ids;
  labels.instance_ids = cv::Mat(ids.height, ids.width, CV_16UC1, const_cast<uint16_t*>(ids.data.data())).clone();
  return labels;
}

}  // namespace mocap::cli
