#include "sim/record/frame_render.h"

#include <filesystem>

#include "core/check.h"

namespace mocap::sim {

SceneMeshes LoadSceneMeshes(const Scenario& scenario, const ObjectLibrary& library, const std::string& library_dir) {
  namespace fs = std::filesystem;
  SceneMeshes meshes;
  for (const ScenarioObject& object : scenario.objects) {
    const ObjectSpec* spec = library.Find(object.name);
    MOCAP_CHECK(spec, "object ", object.name, " not in the library (scenario.check() was not called)");
    meshes.objects.push_back(LoadMesh((fs::path(library_dir) / spec->mesh).string(), spec->unit_scale_to_m));
  }
  for (const ScenarioOccluder& occluder : scenario.occluders)
    meshes.occluders.push_back(LoadMesh((fs::path(library_dir) / occluder.mesh).string(), 1.0));
  return meshes;
}

FrameRenderer::FrameRenderer(const Scenario& scenario, const ObjectLibrary& library, const SceneMeshes& meshes,
                             const RenderContextOptions& context)
    : scenario_(scenario), library_(library), context_(RenderContext::Create(context)) {
  context_->MakeCurrent();
  RendererOptions label_options;
  label_options.outside_margin_fraction = 0;  // the truth needs image pixels only
  labels_ = std::make_unique<Renderer>(*context_, label_options);
  colors_ = std::make_unique<ColorRenderer>(*context_);
  for (const auto* list : {&meshes.objects, &meshes.occluders}) {
    for (const Mesh& mesh : *list) {
      label_handles_.push_back(labels_->Upload(mesh));
      color_handles_.push_back(colors_->Upload(mesh));
    }
  }
}

FrameRenderer::~FrameRenderer() = default;

SimFrame FrameRenderer::Render(const FrameTruth& truth, const RigCalibration& true_calibration) {
  MOCAP_CHECK(scenario_.options.sensor == SensorKind::kKinect1, "FrameRenderer renders Kinect v1 frames only");
  context_->MakeCurrent();
  std::vector<RenderItem> items;
  std::vector<ColorRenderItem> color_items;
  for (size_t i = 0; i < truth.objects.size(); ++i) {
    const auto id = static_cast<uint16_t>(library_.Find(truth.objects[i].name)->id);
    items.push_back({label_handles_[i], truth.objects[i].T_camera_mesh, id});
    color_items.push_back({color_handles_[i], truth.objects[i].T_color_mesh});
  }
  for (size_t k = 0; k < truth.occluders.size(); ++k) {
    const size_t handle = truth.objects.size() + k;
    items.push_back({label_handles_[handle], truth.occluders[k].T_camera_occluder, static_cast<uint16_t>(kOccluderInstanceBase + k)});
    color_items.push_back({color_handles_[handle], truth.occluders[k].T_camera_occluder});
  }
  const PinholeCamera& camera = true_calibration.color_camera;
  RenderOutput clean = labels_->Render(camera, items);
  const ColorImage clean_color = colors_->Render(camera, color_items);
  const uint64_t seed = scenario_.options.seed * 0x100000001b3ULL + static_cast<uint64_t>(truth.index) + 1;
  Kinect1Frame sensor = SimulateKinect1(clean.depth_m, clean_color, camera, scenario_.options.kinect1, seed);
  SimFrame frame;
  frame.index = truth.index;
  frame.color = std::move(sensor.color);
  frame.depth_m = std::move(sensor.depth_m);
  frame.raw_disparity = std::move(sensor.raw_disparity);
  frame.true_instances = std::move(clean.instance_ids);
  frame.invalid_depth_pixels = sensor.shadow_pixels + sensor.edge_pixels + sensor.out_of_range_pixels;
  return frame;
}

}  // namespace mocap::sim
