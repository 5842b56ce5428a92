#include "pipeline/visible_masks.h"

#include "core/check.h"
#include "label/object_labels.h"
#include "render/mesh.h"

namespace mocap::pipeline {

VisibleMaskRenderer::VisibleMaskRenderer(const std::vector<LabelObject>& objects, const PinholeCamera& camera,
                                         const RenderContextOptions& context, const VisibilityOptions& visibility)
    : camera_(camera), visibility_(visibility), context_(RenderContext::Create(context)) {
  context_->MakeCurrent();
  RendererOptions options;
  options.outside_margin_fraction = 0;  // image pixels only: no amodal statistics are needed
  renderer_ = std::make_unique<Renderer>(*context_, options);
  for (const LabelObject& o : objects) handles_[o.name] = renderer_->Upload(LoadMesh(o.mesh_path.string(), o.unit_scale_to_m));
}

VisibleMaskRenderer::~VisibleMaskRenderer() = default;

std::map<uint16_t, Image<uint8_t>> VisibleMaskRenderer::Masks(const std::vector<LabelledPose>& poses,
                                                              const DepthImage& measured_depth_m) {
  context_->MakeCurrent();
  std::vector<RenderItem> items;
  for (const LabelledPose& p : poses) {
    const auto handle = handles_.find(p.object);
    if (handle == handles_.end()) throw InputError("labels", "record names object '" + p.object + "' not in the library");
    items.push_back({handle->second, p.T_camera_mesh, p.instance});
  }
  const RenderOutput render = renderer_->Render(camera_, items);
  const std::vector<ObjectLabels> labels = ComputeObjectLabels(render, camera_, &measured_depth_m, visibility_);
  std::map<uint16_t, Image<uint8_t>> masks;
  for (const ObjectLabels& l : labels)
    masks[l.masks.instance_id] = ToFullImage(l.masks.visible_measured, l.masks.rect, camera_.width, camera_.height, 1);
  return masks;
}

}  // namespace mocap::pipeline
