#include "sim/record/frame_render.h"

#include <filesystem>

#include "core/check.h"

namespace mocap::sim {

SceneMeshes LoadSceneMeshes(const Scenario& scenario, const SimObjects& library, const std::string& library_dir) {
  namespace fs = std::filesystem;
  SceneMeshes meshes;
  for (const ScenarioObject& object : scenario.objects) {
    const SimObject* spec = library.Find(object.name);
    MOCAP_CHECK(spec, "object ", object.name, " not in the library (scenario.check() was not called)");
    meshes.objects.push_back(LoadMesh((fs::path(library_dir) / spec->mesh).string(), spec->unit_scale_to_m));
  }
  for (const ScenarioOccluder& occluder : scenario.occluders)
    meshes.occluders.push_back(LoadMesh((fs::path(library_dir) / occluder.mesh).string(), 1.0));
  return meshes;
}

FrameRenderer::FrameRenderer(const Scenario& scenario, const SimObjects& library, const SceneMeshes& meshes,
                             const RenderContextOptions& context)
    : scenario_(scenario), library_(library), context_(RenderContext::Create(context)) {
  for (const ScenarioObject& object : scenario.objects) {
    const SimObject* spec = library.Find(object.name);
    if (spec->reflectivity > 0)
      reflective_.push_back({static_cast<uint16_t>(spec->id), spec->reflectivity, spec->tof_deformation_m});
    if (object.depth_loss > 0) depth_loss_.fraction_by_instance.emplace_back(static_cast<uint16_t>(spec->id), object.depth_loss);
  }
  for (size_t k = 0; k < scenario.occluders.size(); ++k)
    if (scenario.occluders[k].depth_loss > 0)
      depth_loss_.fraction_by_instance.emplace_back(static_cast<uint16_t>(kOccluderInstanceBase + k),
                                                    scenario.occluders[k].depth_loss);
  context_->MakeCurrent();
  RendererOptions label_options;
  label_options.outside_margin_fraction = 0;  // the truth needs image pixels only
  labels_ = std::make_unique<Renderer>(*context_, label_options);
  color_labels_ = std::make_unique<Renderer>(*context_, label_options);  // Kinect v2: ids in the colour camera
  colors_ = std::make_unique<ColorRenderer>(*context_);
  for (const auto* list : {&meshes.objects, &meshes.occluders}) {
    for (const Mesh& mesh : *list) {
      label_handles_.push_back(labels_->Upload(mesh));
      color_label_handles_.push_back(color_labels_->Upload(mesh));
      color_handles_.push_back(colors_->Upload(mesh));
    }
  }
}

FrameRenderer::~FrameRenderer() = default;

SimFrame FrameRenderer::Render(const FrameTruth& truth, const RigCalibration& true_calibration) {
  context_->MakeCurrent();
  // Objects by library id, then occluders; the colour frame sees the scene at the colour exposure, the
  // depth frame at the depth exposure (the same instant and frame for a Kinect v1).
  std::vector<RenderItem> depth_items, color_ids;
  std::vector<ColorRenderItem> color_items;
  for (size_t i = 0; i < truth.objects.size(); ++i) {
    const auto id = static_cast<uint16_t>(library_.Find(truth.objects[i].name)->id);
    depth_items.push_back({label_handles_[i], truth.objects[i].T_camera_mesh, id});
    color_ids.push_back({color_label_handles_[i], truth.objects[i].T_color_mesh, id});
    color_items.push_back({color_handles_[i], truth.objects[i].T_color_mesh});
  }
  const Rigid3d T_color_depth = true_calibration.T_color_depth;
  for (size_t k = 0; k < truth.occluders.size(); ++k) {
    const size_t handle = truth.objects.size() + k;
    const auto id = static_cast<uint16_t>(kOccluderInstanceBase + k);
    // T_camera_occluder is in the depth frame at the depth exposure; the hand moves slowly enough that
    // the colour frame's few milliseconds of delay are not modelled for it.
    const Rigid3d T_color_occluder = T_color_depth * truth.occluders[k].T_camera_occluder;
    depth_items.push_back({label_handles_[handle], truth.occluders[k].T_camera_occluder, id});
    color_ids.push_back({color_label_handles_[handle], T_color_occluder, id});
    color_items.push_back({color_handles_[handle], T_color_occluder});
  }
  const uint64_t seed = scenario_.options.seed * 0x100000001b3ULL + static_cast<uint64_t>(truth.index) + 1;
  const ColorImage clean_color = colors_->Render(true_calibration.color_camera, color_items);
  RenderOutput clean = labels_->Render(true_calibration.depth_camera, depth_items);
  SimFrame frame;
  frame.index = truth.index;
  if (scenario_.options.sensor == SensorKind::kKinect1) {
    Kinect1Frame sensor = SimulateKinect1(clean.depth_m, clean_color, true_calibration.color_camera,
                                          scenario_.options.kinect1, seed, depth_loss_, &clean.instance_ids);
    frame.color = std::move(sensor.color);
    frame.depth_m = std::move(sensor.depth_m);
    frame.raw_disparity = std::move(sensor.raw_disparity);
    frame.true_instances = std::move(clean.instance_ids);
    frame.invalid_depth_pixels = sensor.shadow_pixels + sensor.edge_pixels + sensor.out_of_range_pixels + sensor.lost_pixels;
    return frame;
  }
  Kinect2DepthFrame depth = SimulateKinect2Depth(clean.depth_m, clean.instance_ids, true_calibration.depth_camera,
                                                 reflective_, scenario_.options.kinect2, seed);
  frame.color = SimulateKinect2Color(clean_color, scenario_.options.kinect2, seed ^ 0x5bd1e995ULL);
  frame.depth_m = std::move(depth.depth_m);
  frame.true_instances = std::move(color_labels_->Render(true_calibration.color_camera, color_ids).instance_ids);
  frame.invalid_depth_pixels = depth.grazing_pixels + depth.out_of_range_pixels;
  return frame;
}

}  // namespace mocap::sim
