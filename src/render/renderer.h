#pragma once
// Label rendering: meshes at poses into a camera, giving per-object amodal depth layers (each object
// alone, for BOP's `mask`) and the z-buffered instance-id and depth images of all objects together
// (for `mask_visib` by the model and for the label PNGs).
//
// Each object is rasterised once, alone, inside the screen rectangle its bounding box projects to, and
// only that rectangle is cleared and read back; the combined z-buffer is the per-pixel nearest of the
// layers (computed on the CPU; identical to a joint z-buffered pass, and exact in metres rather than
// quantised to a 24-bit depth buffer). Successive objects go to different framebuffers so the CPU
// rasteriser (llvmpipe) can rasterise one while the next one's vertices are being processed.
//
// Thread safety: a Renderer uses the GL context current on its thread; one Renderer per RenderContext
// per thread.
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "core/rigid3.h"
#include "render/canvas.h"
#include "render/mesh.h"
#include "render/mesh_closure.h"
#include "render/render_context.h"

namespace mocap {

/// An uploaded mesh (index into the Renderer's meshes).
struct MeshHandle {
  int index = -1;
};

struct RenderItem {
  MeshHandle mesh;
  Rigid3d T_camera_mesh;     ///< mesh frame into the OpenCV camera frame, metres
  uint16_t instance_id = 0;  ///< written into the instance image; > 0
};

/// One object rendered alone (its amodal silhouette and depth).
struct ObjectLayer {
  uint16_t instance_id = 0;
  PixelRect rect;              ///< image pixels this layer covers (within the image)
  std::vector<float> depth_m;  ///< rect.width * rect.height, z along the optical axis; 0 = not covered
  /// Pixels of the amodal silhouette, including those outside the image (within the render canvas).
  int px_count_all = 0;
  /// Amodal bounding box [x, y, w, h] in image pixels including parts outside the image, as BOP writes
  /// it: w = x_max - x_min, h = y_max - y_min; {-1, -1, -1, -1} when the object covers no pixel.
  std::array<int, 4> bbox_obj{-1, -1, -1, -1};
  /// The silhouette reaches the border of the render canvas: bbox_obj and px_count_all are lower bounds.
  bool truncated_by_canvas = false;

  /// Depth at image pixel (u, v), 0 outside the silhouette.
  float depth_at(int u, int v) const {
    return rect.contains(u, v) ? depth_m[static_cast<size_t>(v - rect.y) * rect.width + (u - rect.x)] : 0.0f;
  }
};

struct RenderOutput {
  LabelImage instance_ids;          ///< nearest object's instance id per pixel, 0 = background
  DepthImage depth_m;               ///< nearest object's z (metres), 0 = background
  std::vector<ObjectLayer> layers;  ///< one per RenderItem, same order
};

struct RendererOptions {
  double near_m = 0.02;  ///< clip range along the optical axis
  double far_m = 20.0;
  /// Canvas margin on each side as a fraction of the image size, so that bbox_obj / px_count_all include
  /// parts outside the image (1.0 = BOP's 3x canvas). Costs memory only: rasterisation is clipped to
  /// each object's projected bounding box.
  double outside_margin_fraction = 1.0;
  /// Which meshes are drawn without their back faces (triangles facing away from the camera), for meshes
  /// uploaded without their own choice. Culling about halves the CPU rasteriser's triangle setup.
  BackFaceCulling back_face_culling = BackFaceCulling::kNever;
  /// Framebuffers in flight (pipelining on CPU rasterisers).
  int framebuffers = 3;
  void check() const;  ///< throws InputError
};

class Renderer {
 public:
  /// Precondition: `context` is current on this thread and outlives the Renderer.
  explicit Renderer(const RenderContext& context, const RendererOptions& options = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Uploads the mesh's geometry once; render it any number of times by the handle. Culls its back faces
  /// as options().back_face_culling or `culling` says (kAuto analyses the mesh once, here).
  MeshHandle Upload(const Mesh& mesh);
  MeshHandle Upload(const Mesh& mesh, BackFaceCulling culling);
  /// Whether the mesh's back faces are culled (in draws with its box beyond the near plane).
  bool CullsBackFaces(MeshHandle mesh) const;
  /// Renders `items` into `camera` (its distortion included). Precondition: handles come from Upload,
  /// instance ids are > 0. Throws InputError for an invalid camera.
  RenderOutput Render(const PinholeCamera& camera, std::span<const RenderItem> items);
  /// Same, into `out`, reusing its buffers (no per-frame allocation when called in a loop).
  void Render(const PinholeCamera& camera, std::span<const RenderItem> items, RenderOutput& out);

  /// The canvas used for `camera` (created on first use, cached for the last camera).
  const RenderCanvas& CanvasFor(const PinholeCamera& camera);

 private:
  struct Gl;
  void CheckCanvasFits(const PinholeCamera& camera, const CanvasIntrinsics& canvas) const;

  std::unique_ptr<Gl> gl_;
  RendererOptions options_;
  int max_canvas_px_ = 0;       ///< the GL's largest renderbuffer and viewport side
  std::string gl_renderer_;     ///< for messages
  std::unique_ptr<RenderCanvas> canvas_;
};

}  // namespace mocap
