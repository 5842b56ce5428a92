#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/check.h"
#include "render/gl.h"
#include "render/gl_program.h"
#include "render/mesh_closure.h"

namespace mocap {
namespace {

// z along the optical axis is computed from the camera-from-mesh row directly, so the fragment writes
// metric depth (perspective-correct interpolation of a camera-space attribute is exact at pixel centres).
constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position_mesh;
uniform mat4 clip_from_mesh;
uniform vec4 z_row;  // third row of camera_from_mesh
out float z_camera;
void main() {
  vec4 p = vec4(position_mesh, 1.0);
  z_camera = dot(z_row, p);
  gl_Position = clip_from_mesh * p;
})";

constexpr const char* kFragmentShader = R"(#version 330 core
in float z_camera;
layout(location = 0) out float depth_m;
void main() { depth_m = z_camera; })";

struct GpuMesh {
  GLuint vao = 0, vbo = 0, ebo = 0;
  GLsizei index_count = 0;
  std::array<Eigen::Vector3d, 8> box_corners_m;
  bool cull_back_faces = false;
};

}  // namespace

struct Renderer::Gl {
  GLuint program = 0;
  GLint clip_from_mesh = -1, z_row = -1;
  std::vector<GpuMesh> meshes;
  std::vector<gl::Framebuffer> framebuffers;
  std::vector<float> readback;  // reused between frames

  ~Gl() {
    for (auto& m : meshes) {
      glDeleteVertexArrays(1, &m.vao);
      glDeleteBuffers(1, &m.vbo);
      glDeleteBuffers(1, &m.ebo);
    }
    for (auto& f : framebuffers) f.Release();
    if (program) glDeleteProgram(program);
  }
};

namespace {

/// Canvas pixels the mesh's bounding box projects to (+1 px), clamped to the canvas; the whole canvas
/// when a corner is not beyond the near plane (`beyond_near` false: the camera may be inside the mesh).
PixelRect ProjectedRect(const GpuMesh& mesh, const Rigid3d& T_camera_mesh, const CanvasIntrinsics& c, double near_m,
                        bool& beyond_near) {
  double u0 = 1e30, v0 = 1e30, u1 = -1e30, v1 = -1e30;
  const PixelRect all{0, 0, c.width, c.height};
  beyond_near = false;
  for (const Eigen::Vector3d& corner : mesh.box_corners_m) {
    const Eigen::Vector3d p = T_camera_mesh * corner;
    if (p.z() < near_m) return all;
    const double u = c.fx * p.x() / p.z() + c.cx, v = c.fy * p.y() / p.z() + c.cy;
    u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
  }
  beyond_near = true;
  const double lo = -1e6, hi = 1e6;  // keep the integer conversion defined for absurd poses
  const int x0 = static_cast<int>(std::floor(std::clamp(u0, lo, hi))) - 1;
  const int y0 = static_cast<int>(std::floor(std::clamp(v0, lo, hi))) - 1;
  const int x1 = static_cast<int>(std::ceil(std::clamp(u1, lo, hi))) + 2;
  const int y1 = static_cast<int>(std::ceil(std::clamp(v1, lo, hi))) + 2;
  return PixelRect{x0, y0, x1 - x0, y1 - y0}.Intersect(all);
}

Eigen::Matrix4f ClipFromMesh(const Eigen::Matrix4f& clip_from_camera, const Rigid3d& T_camera_mesh) {
  return (clip_from_camera.cast<double>() * T_camera_mesh.matrix4()).cast<float>();
}

/// Turns the read-back canvas rectangle of one object into its image layer and amodal statistics
/// (`layer`'s buffer is reused).
void MakeLayer(const RenderCanvas& canvas, const PixelRect& r, const std::vector<float>& canvas_depth,
               uint16_t instance_id, ObjectLayer& layer) {
  layer.instance_id = instance_id;
  layer.px_count_all = 0;
  layer.bbox_obj = {-1, -1, -1, -1};
  layer.truncated_by_canvas = false;
  const CanvasIntrinsics& c = canvas.intrinsics();
  double u0 = 1e30, v0 = 1e30, u1 = -1e30, v1 = -1e30;
  for (int y = r.y; y < r.y + r.height; ++y) {
    for (int x = r.x; x < r.x + r.width; ++x) {
      if (!(canvas_depth[static_cast<size_t>(y - r.y) * r.width + (x - r.x)] > 0.0f)) continue;
      if (x == 0 || y == 0 || x == c.width - 1 || y == c.height - 1) layer.truncated_by_canvas = true;
      if (canvas.distorted() && canvas.InsideImage(x, y)) continue;  // counted after the remap below
      double u, v;
      if (!canvas.ImagePositionOfCanvasPixel(x, y, u, v)) continue;
      ++layer.px_count_all;
      u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
    }
  }
  layer.rect = canvas.ImageRectOf(r);
  layer.depth_m.assign(static_cast<size_t>(std::max(0, layer.rect.width * layer.rect.height)), 0.0f);
  const PixelRect& ir = layer.rect;
  for (int v = ir.y; v < ir.y + ir.height; ++v) {
    for (int u = ir.x; u < ir.x + ir.width; ++u) {
      const int32_t index = canvas.CanvasIndexOfImagePixel(u, v);
      if (index < 0) continue;
      const int x = index % c.width, y = index / c.width;
      if (!r.contains(x, y)) continue;
      const float z = canvas_depth[static_cast<size_t>(y - r.y) * r.width + (x - r.x)];
      if (!(z > 0.0f)) continue;
      layer.depth_m[static_cast<size_t>(v - ir.y) * ir.width + (u - ir.x)] = z;
      if (canvas.distorted()) {
        ++layer.px_count_all;
        u0 = std::min(u0, double(u)), u1 = std::max(u1, double(u)), v0 = std::min(v0, double(v)), v1 = std::max(v1, double(v));
      }
    }
  }
  if (layer.px_count_all > 0) {
    // Pixel positions are integers without distortion; distorted outside positions are rounded.
    const int x0 = static_cast<int>(std::lround(u0)), y0 = static_cast<int>(std::lround(v0));
    layer.bbox_obj = {x0, y0, static_cast<int>(std::lround(u1)) - x0, static_cast<int>(std::lround(v1)) - y0};
  }
}

/// Nearest-wins composition of one layer into the instance and depth images (ties: earlier layer).
void Composite(const ObjectLayer& layer, RenderOutput& out) {
  const PixelRect& r = layer.rect;
  if (r.empty()) return;  // an object outside the image has no layer pixels (and an empty depth_m)
  for (int v = r.y; v < r.y + r.height; ++v) {
    const float* row = layer.depth_m.data() + static_cast<size_t>(v - r.y) * r.width;
    for (int u = r.x; u < r.x + r.width; ++u) {
      const float z = row[u - r.x];
      if (!(z > 0.0f)) continue;
      float& nearest = out.depth_m.at(u, v);
      if (nearest == 0.0f || z < nearest) nearest = z, out.instance_ids.at(u, v) = layer.instance_id;
    }
  }
}

}  // namespace

void RendererOptions::check() const {
  if (!(near_m > 0) || !(far_m > near_m))
    throw InputError("renderer options", Str("clip range near ", near_m, " m, far ", far_m, " m is invalid"));
  if (!(outside_margin_fraction >= 0) || outside_margin_fraction > 4)
    throw InputError("renderer options", Str("outside_margin_fraction ", outside_margin_fraction, " not in [0, 4]"));
  if (framebuffers < 1 || framebuffers > 16)
    throw InputError("renderer options", Str("framebuffers ", framebuffers, " not in [1, 16]"));
}

Renderer::Renderer(const RenderContext& context, const RendererOptions& options)
    : gl_(std::make_unique<Gl>()), options_(options) {
  options.check();
  context.MakeCurrent();
  gl_->program = gl::LinkProgram(kVertexShader, kFragmentShader);
  gl_->clip_from_mesh = glGetUniformLocation(gl_->program, "clip_from_mesh");
  gl_->z_row = glGetUniformLocation(gl_->program, "z_row");
  gl_->framebuffers.resize(static_cast<size_t>(options.framebuffers));
  GLint max_renderbuffer = 0, max_viewport[2] = {0, 0};
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_renderbuffer);
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, max_viewport);
  max_canvas_px_ = std::min({max_renderbuffer, max_viewport[0], max_viewport[1]});
  gl_renderer_ = context.info().gl_renderer;
  // Image rows map to GL window rows unflipped (conventions.h), which mirrors the winding: a face whose
  // outward normal points at the camera is clockwise in GL window coordinates. Culling is switched on
  // per draw (Render).
  glFrontFace(GL_CW);
  glCullFace(GL_BACK);
  glDisable(GL_CULL_FACE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_SCISSOR_TEST);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  gl::CheckError("renderer setup");
}

Renderer::~Renderer() = default;

MeshHandle Renderer::Upload(const Mesh& mesh) { return Upload(mesh, options_.back_face_culling); }

bool Renderer::CullsBackFaces(MeshHandle mesh) const {
  MOCAP_CHECK(mesh.index >= 0 && mesh.index < static_cast<int>(gl_->meshes.size()), "bad mesh handle");
  return gl_->meshes[static_cast<size_t>(mesh.index)].cull_back_faces;
}

MeshHandle Renderer::Upload(const Mesh& mesh, BackFaceCulling culling) {
  MOCAP_CHECK(!mesh.indices.empty(), "uploading an empty mesh ", mesh.source);
  GpuMesh m;
  m.cull_back_faces = culling == BackFaceCulling::kAlways ||
                      (culling == BackFaceCulling::kAuto && AnalyzeClosure(mesh).culling_exact());
  const Eigen::Vector3d lo = mesh.min_m().cast<double>(), hi = mesh.max_m().cast<double>();
  for (int i = 0; i < 8; ++i)
    m.box_corners_m[i] = {(i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z()};
  glGenVertexArrays(1, &m.vao);
  glBindVertexArray(m.vao);
  glGenBuffers(1, &m.vbo);
  glBindBuffer(GL_ARRAY_BUFFER, m.vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.positions_m.size() * sizeof(Eigen::Vector3f)),
               mesh.positions_m.data(), GL_STATIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Eigen::Vector3f), nullptr);
  glEnableVertexAttribArray(0);
  glGenBuffers(1, &m.ebo);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m.ebo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(uint32_t)),
               mesh.indices.data(), GL_STATIC_DRAW);
  m.index_count = static_cast<GLsizei>(mesh.indices.size());
  glBindVertexArray(0);
  gl::CheckError("mesh upload");
  gl_->meshes.push_back(m);
  return MeshHandle{static_cast<int>(gl_->meshes.size()) - 1};
}

// A canvas beyond the GL's limits makes an incomplete framebuffer (an internal error, formerly an abort);
// a camera that large is an input the user can change, so it is an InputError naming the sizes.
void Renderer::CheckCanvasFits(const PinholeCamera& camera, const CanvasIntrinsics& canvas) const {
  if (canvas.width <= max_canvas_px_ && canvas.height <= max_canvas_px_) return;
  throw InputError(Str("camera ", camera.width, "x", camera.height),
                   Str("its render canvas (the image plus margins of ", options_.outside_margin_fraction,
                       " image per side for amodal boxes) is ", canvas.width, "x", canvas.height,
                       " px, beyond the ", max_canvas_px_, " px per side this OpenGL renders (", gl_renderer_,
                       "); lower the margin (label --outside-margin) or the camera resolution"));
}

const RenderCanvas& Renderer::CanvasFor(const PinholeCamera& camera) {
  if (!canvas_ || !SameCamera(canvas_->camera(), camera))
    canvas_ = std::make_unique<RenderCanvas>(camera, options_.outside_margin_fraction);
  return *canvas_;
}

RenderOutput Renderer::Render(const PinholeCamera& camera, std::span<const RenderItem> items) {
  RenderOutput out;
  Render(camera, items, out);
  return out;
}

/// Sizes `image` to w x h and zeroes it, reusing its memory.
template <typename T>
void ResetImage(Image<T>& image, int w, int h) {
  if (image.width != w || image.height != h) image = Image<T>(w, h);
  else std::fill(image.data.begin(), image.data.end(), T{});
}

void Renderer::Render(const PinholeCamera& camera, std::span<const RenderItem> items, RenderOutput& out) {
  camera.check();
  const RenderCanvas& canvas = CanvasFor(camera);
  const CanvasIntrinsics& c = canvas.intrinsics();
  const Eigen::Matrix4f clip_from_camera = GlClipFromCamera(c, options_.near_m, options_.far_m);
  CheckCanvasFits(camera, c);
  for (auto& f : gl_->framebuffers)
    if (f.width != c.width || f.height != c.height) f.Allocate(c.width, c.height, GL_R32F);

  ResetImage(out.instance_ids, camera.width, camera.height);
  ResetImage(out.depth_m, camera.width, camera.height);
  out.layers.resize(items.size());
  glUseProgram(gl_->program);
  glViewport(0, 0, c.width, c.height);
  const size_t batch = gl_->framebuffers.size();
  std::vector<PixelRect> rects(items.size());
  std::vector<float>& readback = gl_->readback;
  for (size_t first = 0; first < items.size(); first += batch) {
    const size_t last = std::min(items.size(), first + batch);
    for (size_t i = first; i < last; ++i) {  // issue the draws of the batch, one framebuffer each
      const RenderItem& item = items[i];
      MOCAP_CHECK(item.mesh.index >= 0 && item.mesh.index < static_cast<int>(gl_->meshes.size()), "bad mesh handle");
      MOCAP_CHECK(item.instance_id > 0, "instance id 0 is the background");
      const GpuMesh& mesh = gl_->meshes[static_cast<size_t>(item.mesh.index)];
      bool beyond_near = false;
      rects[i] = ProjectedRect(mesh, item.T_camera_mesh, c, options_.near_m, beyond_near);
      if (rects[i].empty()) continue;
      // Exact only with the camera outside the solid: a ray starting inside it meets a back face first.
      if (mesh.cull_back_faces && beyond_near) glEnable(GL_CULL_FACE);
      else glDisable(GL_CULL_FACE);
      glBindFramebuffer(GL_FRAMEBUFFER, gl_->framebuffers[i - first].fbo);
      glScissor(rects[i].x, rects[i].y, rects[i].width, rects[i].height);
      const float zero[4] = {0, 0, 0, 0};
      glClearBufferfv(GL_COLOR, 0, zero);
      const float far_depth = 1.0f;
      glClearBufferfv(GL_DEPTH, 0, &far_depth);
      const Eigen::Matrix4f clip_from_mesh = ClipFromMesh(clip_from_camera, item.T_camera_mesh);
      const Eigen::Vector4f z_row = item.T_camera_mesh.matrix4().row(2).cast<float>();
      glUniformMatrix4fv(gl_->clip_from_mesh, 1, GL_FALSE, clip_from_mesh.data());
      glUniform4fv(gl_->z_row, 1, z_row.data());
      glBindVertexArray(mesh.vao);
      glDrawElements(GL_TRIANGLES, mesh.index_count, GL_UNSIGNED_INT, nullptr);
      glFlush();  // hand the object to the rasteriser threads before the next one's vertices
    }
    for (size_t i = first; i < last; ++i) {  // read back each object's rectangle only
      const PixelRect& r = rects[i];
      readback.assign(static_cast<size_t>(std::max(0, r.width * r.height)), 0.0f);
      if (!r.empty()) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, gl_->framebuffers[i - first].fbo);
        glReadPixels(r.x, r.y, r.width, r.height, GL_RED, GL_FLOAT, readback.data());
      }
      MakeLayer(canvas, r, readback, items[i].instance_id, out.layers[i]);
      Composite(out.layers[i], out);
    }
  }
  glBindVertexArray(0);
  glDisable(GL_CULL_FACE);
  gl::CheckError("render");
}

}  // namespace mocap
