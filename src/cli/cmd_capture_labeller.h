#pragma once
// The labels on the capture daemon's live thumbnails (docs/live-page.md): the labeller's own chain of
// transforms (PoseChain, over the samples the daemon has just received) and renderer, so the overlay
// is what `mocaplabel label` will give the recorded frame. Lives in the CLI because capture knows
// nothing of labelling.
#include <memory>
#include <vector>

#include "capture/daemon/live_view.h"
#include "label/label_objects.h"
#include "label/pose_chain.h"
#include "label/rig.h"
#include "render/render_context.h"
#include "render/renderer.h"

namespace mocap::cli {

class RigFrameLabeller final : public capture::FrameLabeller {
 public:
  /// Loads the meshes now (InputError for one that cannot be read), renders later on the live view's
  /// thread.
  RigFrameLabeller(LabelRig rig, std::vector<LabelObject> objects);
  ~RigFrameLabeller() override;

  std::optional<capture::FrameLabels> Label(const SessionManifest& manifest, const std::string& camera,
                                            const CameraFrameRecord& frame,
                                            const std::map<std::string, std::vector<TrackerRecord>>& samples) override;
  void ThreadEnd() override;

 private:
  void EnsureRenderer();

  LabelRig rig_;
  std::vector<LabelObject> objects_;
  std::vector<Mesh> meshes_;
  PoseChainOptions chain_options_;
  RendererOptions renderer_options_;
  std::unique_ptr<RenderContext> context_;  // made and used on the live view's thread only
  std::unique_ptr<Renderer> renderer_;
  std::vector<MeshHandle> handles_;
};

}  // namespace mocap::cli
