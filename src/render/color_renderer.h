#pragma once
// Colour rendering for the simulator: meshes with their vertex colours and textures, Lambert shading by
// one directional light plus ambient light, over a background colour. Same conventions as the label
// renderer (render/conventions.h): the canvas is the undistorted pinhole grid of the camera and a
// nearest-neighbour lookup maps it onto the distorted image (render/canvas.h), so a pixel's colour comes
// from the same surface point as its instance id and depth in Renderer's output.
//
// All objects are drawn in one z-buffered pass (colours need no per-object layers). No anti-aliasing:
// each pixel shows the surface at its centre, like the labels.
//
// Thread safety: as Renderer, one ColorRenderer per RenderContext per thread.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <span>

#include "core/camera.h"
#include "core/image.h"
#include "core/rigid3.h"
#include "render/canvas.h"
#include "render/mesh.h"
#include "render/render_context.h"
#include "render/renderer.h"

namespace mocap {

using Rgb8Pixel = std::array<uint8_t, 3>;  ///< red, green, blue
using RgbImage = Image<Rgb8Pixel>;

struct ColorRenderItem {
  MeshHandle mesh;         ///< from ColorRenderer::Upload
  Rigid3d T_camera_mesh;   ///< mesh frame into the OpenCV camera frame, metres
};

struct ColorRendererOptions {
  double near_m = 0.02;  ///< clip range along the optical axis
  double far_m = 20.0;
  /// Direction *towards* the light in the camera frame (need not be unit); the default lights the scene
  /// from above-left of the camera, as a room light would.
  Eigen::Vector3d light_dir_camera{-0.3, -0.8, -0.5};
  double ambient = 0.35;  ///< fraction of the base colour lit by ambient light, [0, 1]
  double diffuse = 0.65;  ///< Lambert term's weight, [0, 1]
  Eigen::Vector3d background_rgb{0.18, 0.20, 0.24};  ///< [0, 1] per channel
  /// Colour of meshes without vertex colours or texture, [0, 1].
  Eigen::Vector3d default_rgb{0.7, 0.7, 0.7};
  void check() const;  ///< throws InputError
};

class ColorRenderer {
 public:
  /// Precondition: `context` is current on this thread and outlives the renderer.
  explicit ColorRenderer(const RenderContext& context, const ColorRendererOptions& options = {});
  ~ColorRenderer();
  ColorRenderer(const ColorRenderer&) = delete;
  ColorRenderer& operator=(const ColorRenderer&) = delete;

  /// Uploads geometry, vertex colours, uvs and the texture once. Precondition: mesh not empty.
  MeshHandle Upload(const Mesh& mesh);
  /// Renders `items` into `camera` (distortion included) as 8-bit RGB; the shading scales the meshes'
  /// stored colour values directly (no gamma handling). Throws InputError for an invalid camera.
  RgbImage Render(const PinholeCamera& camera, std::span<const ColorRenderItem> items);

 private:
  struct Gl;
  std::unique_ptr<Gl> gl_;
  ColorRendererOptions options_;
  std::unique_ptr<RenderCanvas> canvas_;
};

}  // namespace mocap
