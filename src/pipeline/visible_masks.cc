#include "pipeline/visible_masks.h"

#include <optional>

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
  for (const LabelObject& o : objects) {
    const Mesh mesh = LoadMesh(o.mesh_path.string(), o.unit_scale_to_m);
    handles_[o.name] = renderer_->Upload(mesh);
    if (visibility_.hole_colour) mesh_colours_.emplace(o.name, MeshColours(mesh, visibility_));
  }
}

VisibleMaskRenderer::~VisibleMaskRenderer() = default;

std::map<uint16_t, Image<uint8_t>> VisibleMaskRenderer::Masks(const std::vector<LabelledPose>& poses,
                                                              const DepthImage& measured_depth_m,
                                                              const BgrView* color) {
  context_->MakeCurrent();
  std::vector<RenderItem> items;
  for (const LabelledPose& p : poses) {
    const auto handle = handles_.find(p.object);
    if (handle == handles_.end()) throw InputError("labels", "record names object '" + p.object + "' not in the library");
    items.push_back({handle->second, p.T_camera_mesh, p.instance});
  }
  const RenderOutput render = renderer_->Render(camera_, items);
  std::optional<HoleColours> colours;
  if (color) {
    colours.emplace(HoleColours{*color, {}});
    for (const LabelledPose& p : poses)
      if (const auto it = mesh_colours_.find(p.object); it != mesh_colours_.end()) colours->mesh_colours[p.instance] = &it->second;
  }
  const std::vector<ObjectLabels> labels =
      ComputeObjectLabels(render, camera_, &measured_depth_m, visibility_, colours ? &*colours : nullptr);
  std::map<uint16_t, Image<uint8_t>> masks;
  for (const ObjectLabels& l : labels)
    masks[l.masks.instance_id] = ToFullImage(l.masks.visible_measured, l.masks.rect, camera_.width, camera_.height, 1);
  return masks;
}

}  // namespace mocap::pipeline
