#pragma once
// Model crops rendered by the EGL renderer (src/render), as the paper makes them: the mesh is rendered at
// the hypothesis pose into a virtual camera, and the depth image is back-projected into the model frame,
// one point per pixel. Hidden surfaces are removed by the GPU's (or llvmpipe's) depth test on the mesh
// itself, not on surface samples, so thin walls and concave parts come out exactly.
#include <memory>

#include "render/mesh.h"
#include "render/render_context.h"
#include "validate/model_crop.h"

namespace mocap {

/// The geometry of a render mesh as the validator's TriangleMesh (metres, model frame).
TriangleMesh ToTriangleMesh(const Mesh& mesh);

/// A CropSource backed by the renderer. The virtual camera sits at the camera centre of `T_camera_model`
/// and looks at the model's bounding-sphere centre (visibility depends only on the camera centre, so
/// turning the camera changes nothing but keeps the model in the image); its focal length makes one
/// pixel span `CropOptions::pixel_m` at that centre's distance, so the crops have the resolution of
/// SurfaceCropSource's.
///
/// Thread safety: Crop may be called from any number of threads. A GL context belongs to one thread,
/// so the source owns a render thread that holds the context; calls queue their renders there and
/// back-project on their own thread.
class RenderedCropSource : public CropSource {
 public:
  /// Creates the render thread and its context. Throws InputError for an empty mesh or bad options,
  /// std::runtime_error when no EGL context can be created (see RenderContext::Create).
  RenderedCropSource(const Mesh& mesh, const CropOptions& options, const RenderContextOptions& context = {});
  ~RenderedCropSource() override;
  RenderedCropSource(const RenderedCropSource&) = delete;
  RenderedCropSource& operator=(const RenderedCropSource&) = delete;

  ModelCrop Crop(const Rigid3d& T_camera_model) const override;
  /// The mesh vertices (model frame): enough for bounding boxes and centres.
  const PointCloud& surface_model() const override { return vertices_; }

 private:
  class RenderThread;
  std::unique_ptr<RenderThread> thread_;
  PointCloud vertices_;
  CropOptions options_;
  Eigen::Vector3d center_model_;  ///< bounding-box centre
  double radius_m_ = 0.0;         ///< bounding-sphere radius about center_model_
};

}  // namespace mocap
