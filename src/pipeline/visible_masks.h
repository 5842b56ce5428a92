#pragma once
// The label's visible masks of one frame computed in process from the labelled poses, as the labeller
// computes them (label/object_labels.h): the meshes rendered at the poses of labels.jsonl, then the
// visibility rule against the session's measured depth (in the colour image) and, for the colour test
// on holes, its colour image, which see what the labeller has no model of (the hand). Scoring uses these
// rather than the instance images, whose z-buffer knows only the objects.
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "core/rigid3.h"
#include "label/hole_colour.h"
#include "label/label_objects.h"
#include "label/visibility.h"
#include "render/render_context.h"
#include "render/renderer.h"

namespace mocap::pipeline {

/// One labelled instance of a frame.
struct LabelledPose {
  std::string object;      ///< LabelObject name
  uint16_t instance = 0;   ///< labels.jsonl `instance`
  Rigid3d T_camera_mesh;
};

class VisibleMaskRenderer {
 public:
  /// Loads the meshes of `objects` and creates an EGL context on this thread. Throws InputError for a
  /// mesh that cannot be loaded.
  VisibleMaskRenderer(const std::vector<LabelObject>& objects, const PinholeCamera& camera,
                      const RenderContextOptions& context, const VisibilityOptions& visibility = {});
  ~VisibleMaskRenderer();
  /// Full-image masks (1 = visible) per instance. Precondition: measured depth has the camera's size.
  /// `color`: the frame's colour image, for the optional colour test on holes (may be null).
  std::map<uint16_t, Image<uint8_t>> Masks(const std::vector<LabelledPose>& poses, const DepthImage& measured_depth_m,
                                           const BgrView* color = nullptr);
  const PinholeCamera& camera() const { return camera_; }
  const VisibilityOptions& visibility() const { return visibility_; }

 private:
  PinholeCamera camera_;
  VisibilityOptions visibility_;
  std::unique_ptr<RenderContext> context_;
  std::unique_ptr<Renderer> renderer_;
  std::map<std::string, MeshHandle> handles_;
  std::map<std::string, ColourHistogram> mesh_colours_;  ///< with the colour test on holes only
};

}  // namespace mocap::pipeline
