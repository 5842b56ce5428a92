#pragma once
// One simulated frame: the scene rendered at the truth's poses (clean colour, depth and instance ids)
// and passed through the sensor model. Each worker thread owns one FrameRenderer (and its EGL context).
#include <cstdint>
#include <memory>
#include <vector>

#include "core/image.h"
#include "render/color_renderer.h"
#include "render/mesh.h"
#include "render/render_context.h"
#include "render/renderer.h"
#include "sim/color_image.h"
#include "sim/depth_loss.h"
#include "sim/scenario.h"
#include "sim/truth.h"

namespace mocap::sim {

/// Instance id of occluder k in the truth's instance images: above every object id of a library.
constexpr uint16_t kOccluderInstanceBase = 65000;

/// The meshes of a scenario in scenario order (objects, then occluders), loaded once and shared by
/// the workers (read only).
struct SceneMeshes {
  std::vector<Mesh> objects;
  std::vector<Mesh> occluders;
};

/// Loads the meshes of `scenario` from `library_dir` (the folder of objects.yaml). Throws InputError
/// naming a missing or unreadable mesh.
SceneMeshes LoadSceneMeshes(const Scenario& scenario, const SimObjects& library, const std::string& library_dir);

struct SimFrame {
  int index = 0;
  ColorImage color;              ///< what the sensor delivers (noise applied)
  DepthImage depth_m;            ///< what the sensor delivers (Kinect v1: registered to colour; v2: IR camera); 0 = none
  Image<uint16_t> raw_disparity; ///< Kinect v1 11-bit disparity (2047 = none); empty for Kinect v2
  LabelImage true_instances;     ///< truth in the colour image: object (library) id or occluder id, 0 = nothing
  int invalid_depth_pixels = 0;  ///< dropped by the sensor model (shadow, edges, range, dark or shiny surfaces)
};

class FrameRenderer {
 public:
  /// Creates this thread's EGL context and uploads the meshes. `meshes` must outlive the renderer.
  FrameRenderer(const Scenario& scenario, const SimObjects& library, const SceneMeshes& meshes,
                const RenderContextOptions& context);
  ~FrameRenderer();
  /// Renders and sensor-models frame `truth` (Kinect v1 or v2). Reproducible: noise is seeded by the
  /// scenario's seed and the frame index only.
  SimFrame Render(const FrameTruth& truth, const RigCalibration& true_calibration);

 private:
  const Scenario& scenario_;
  const SimObjects& library_;
  std::unique_ptr<RenderContext> context_;
  std::unique_ptr<Renderer> labels_, color_labels_;
  std::unique_ptr<ColorRenderer> colors_;
  std::vector<MeshHandle> label_handles_, color_label_handles_, color_handles_;  // objects then occluders
  std::vector<ReflectiveSurface> reflective_;
  DepthLoss depth_loss_;  ///< dark or shiny objects and occluders (Kinect v1)
};

}  // namespace mocap::sim
