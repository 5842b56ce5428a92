#include "render/color_renderer.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/check.h"
#include "render/gl.h"
#include "render/gl_program.h"

namespace mocap {
namespace {

constexpr const char* kColorVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position_mesh;
layout(location = 1) in vec4 color;
layout(location = 2) in vec2 uv;
uniform mat4 clip_from_mesh;
uniform mat4 camera_from_mesh;
out vec3 position_camera;
out vec4 vertex_color;
out vec2 vertex_uv;
void main() {
  vec4 p = vec4(position_mesh, 1.0);
  position_camera = (camera_from_mesh * p).xyz;
  vertex_color = color;
  vertex_uv = uv;
  gl_Position = clip_from_mesh * p;
})";

// The face normal comes from the screen-space derivatives of the camera-space position (flat shading,
// no normals needed in the mesh) and is turned towards the camera, since the winding is mirrored by the
// image-row convention and scanned meshes are not consistently oriented.
constexpr const char* kColorFragmentShader = R"(#version 330 core
in vec3 position_camera;
in vec4 vertex_color;
in vec2 vertex_uv;
uniform sampler2D diffuse_texture;
uniform int has_texture;
uniform vec3 light_dir;
uniform float ambient;
uniform float diffuse;
layout(location = 0) out vec4 rgba;
void main() {
  vec3 n = normalize(cross(dFdx(position_camera), dFdy(position_camera)));
  if (dot(n, position_camera) > 0.0) n = -n;
  vec3 base = vertex_color.rgb;
  if (has_texture != 0) base *= texture(diffuse_texture, vertex_uv).rgb;
  float shade = ambient + diffuse * max(dot(n, light_dir), 0.0);
  rgba = vec4(clamp(base * shade, 0.0, 1.0), 1.0);
})";

struct GpuColorMesh {
  GLuint vao = 0, vbo = 0, ebo = 0, texture = 0;
  GLsizei index_count = 0;
};

struct Vertex {
  float position[3];
  float color[4];
  float uv[2];
};

std::vector<Vertex> Interleave(const Mesh& mesh) {
  std::vector<Vertex> vertices(mesh.positions_m.size());
  for (size_t i = 0; i < vertices.size(); ++i) {
    Vertex& v = vertices[i];
    const Eigen::Vector3f& p = mesh.positions_m[i];
    const Eigen::Vector4f c = i < mesh.colors.size() ? mesh.colors[i] : Eigen::Vector4f(-1, -1, -1, 1);
    const Eigen::Vector2f t = i < mesh.uvs.size() ? mesh.uvs[i] : Eigen::Vector2f::Zero();
    v = {{p.x(), p.y(), p.z()}, {c.x(), c.y(), c.z(), c.w()}, {t.x(), t.y()}};
  }
  return vertices;
}

GLuint UploadTexture(const TextureRgb8& texture) {
  GLuint id = 0;
  glGenTextures(1, &id);
  glBindTexture(GL_TEXTURE_2D, id);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  // Row 0 of TextureRgb8 is the top of the image; GL's t = 0 is the first row uploaded, and uv (0, 0)
  // is the bottom-left of the texture, so upload bottom row first.
  std::vector<uint8_t> flipped(texture.rgb.size());
  const size_t row = static_cast<size_t>(texture.width) * 3;
  for (int r = 0; r < texture.height; ++r)
    std::copy_n(&texture.rgb[static_cast<size_t>(texture.height - 1 - r) * row], row, &flipped[static_cast<size_t>(r) * row]);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, texture.width, texture.height, 0, GL_RGB, GL_UNSIGNED_BYTE, flipped.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
  return id;
}

}  // namespace

struct ColorRenderer::Gl {
  GLuint program = 0;
  GLint clip_from_mesh = -1, camera_from_mesh = -1, has_texture = -1, light_dir = -1, ambient = -1, diffuse = -1;
  std::vector<GpuColorMesh> meshes;
  gl::Framebuffer framebuffer;
  std::vector<uint8_t> readback;

  ~Gl() {
    for (auto& m : meshes) {
      glDeleteVertexArrays(1, &m.vao);
      glDeleteBuffers(1, &m.vbo);
      glDeleteBuffers(1, &m.ebo);
      if (m.texture) glDeleteTextures(1, &m.texture);
    }
    framebuffer.Release();
    if (program) glDeleteProgram(program);
  }
};

void ColorRendererOptions::check() const {
  if (!(near_m > 0) || !(far_m > near_m))
    throw InputError("colour renderer options", Str("clip range near ", near_m, " m, far ", far_m, " m is invalid"));
  if (!(light_dir_camera.norm() > 0)) throw InputError("colour renderer options", "light_dir_camera is zero");
  for (double w : {ambient, diffuse})
    if (!(w >= 0 && w <= 1)) throw InputError("colour renderer options", Str("ambient/diffuse weight ", w, " not in [0, 1]"));
  for (const Eigen::Vector3d* c : {&background_rgb, &default_rgb})
    if (!(c->minCoeff() >= 0 && c->maxCoeff() <= 1))
      throw InputError("colour renderer options", "background_rgb / default_rgb must be in [0, 1]");
}

ColorRenderer::ColorRenderer(const RenderContext& context, const ColorRendererOptions& options)
    : gl_(std::make_unique<Gl>()), options_(options) {
  options.check();
  context.MakeCurrent();
  Gl& g = *gl_;
  g.program = gl::LinkProgram(kColorVertexShader, kColorFragmentShader);
  g.clip_from_mesh = glGetUniformLocation(g.program, "clip_from_mesh");
  g.camera_from_mesh = glGetUniformLocation(g.program, "camera_from_mesh");
  g.has_texture = glGetUniformLocation(g.program, "has_texture");
  g.light_dir = glGetUniformLocation(g.program, "light_dir");
  g.ambient = glGetUniformLocation(g.program, "ambient");
  g.diffuse = glGetUniformLocation(g.program, "diffuse");
  gl::CheckError("colour renderer setup");
}

ColorRenderer::~ColorRenderer() = default;

MeshHandle ColorRenderer::Upload(const Mesh& mesh) {
  MOCAP_CHECK(!mesh.indices.empty(), "uploading an empty mesh ", mesh.source);
  std::vector<Vertex> vertices = Interleave(mesh);
  for (Vertex& v : vertices)  // meshes without vertex colours get the default colour
    if (v.color[0] < 0)
      for (int c = 0; c < 3; ++c) v.color[c] = static_cast<float>(options_.default_rgb[c]);
  GpuColorMesh m;
  glGenVertexArrays(1, &m.vao);
  glBindVertexArray(m.vao);
  glGenBuffers(1, &m.vbo);
  glBindBuffer(GL_ARRAY_BUFFER, m.vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)), vertices.data(), GL_STATIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, position)));
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, color)));
  glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, uv)));
  for (GLuint a = 0; a < 3; ++a) glEnableVertexAttribArray(a);
  glGenBuffers(1, &m.ebo);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m.ebo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(uint32_t)),
               mesh.indices.data(), GL_STATIC_DRAW);
  m.index_count = static_cast<GLsizei>(mesh.indices.size());
  glBindVertexArray(0);
  if (!mesh.texture.empty() && mesh.uvs.size() == mesh.positions_m.size()) m.texture = UploadTexture(mesh.texture);
  gl::CheckError("colour mesh upload");
  gl_->meshes.push_back(m);
  return MeshHandle{static_cast<int>(gl_->meshes.size()) - 1};
}

RgbImage ColorRenderer::Render(const PinholeCamera& camera, std::span<const ColorRenderItem> items) {
  camera.check();
  if (!canvas_ || !SameCamera(canvas_->camera(), camera)) canvas_ = std::make_unique<RenderCanvas>(camera, 0.0);
  const CanvasIntrinsics& c = canvas_->intrinsics();
  Gl& g = *gl_;
  if (g.framebuffer.width != c.width || g.framebuffer.height != c.height) g.framebuffer.Allocate(c.width, c.height, GL_RGBA8);
  glBindFramebuffer(GL_FRAMEBUFFER, g.framebuffer.fbo);
  glViewport(0, 0, c.width, c.height);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_CULL_FACE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  const Eigen::Vector3d& bg = options_.background_rgb;
  const float background[4] = {float(bg.x()), float(bg.y()), float(bg.z()), 1.0f}, far_depth = 1.0f;
  glClearBufferfv(GL_COLOR, 0, background);
  glClearBufferfv(GL_DEPTH, 0, &far_depth);
  glUseProgram(g.program);
  const Eigen::Vector3f light = options_.light_dir_camera.normalized().cast<float>();
  glUniform3fv(g.light_dir, 1, light.data());
  glUniform1f(g.ambient, static_cast<float>(options_.ambient));
  glUniform1f(g.diffuse, static_cast<float>(options_.diffuse));
  glUniform1i(glGetUniformLocation(g.program, "diffuse_texture"), 0);
  glActiveTexture(GL_TEXTURE0);
  const Eigen::Matrix4d clip_from_camera = GlClipFromCamera(c, options_.near_m, options_.far_m).cast<double>();
  for (const ColorRenderItem& item : items) {
    MOCAP_CHECK(item.mesh.index >= 0 && item.mesh.index < static_cast<int>(g.meshes.size()), "bad mesh handle");
    const GpuColorMesh& mesh = g.meshes[static_cast<size_t>(item.mesh.index)];
    const Eigen::Matrix4f camera_from_mesh = item.T_camera_mesh.matrix4().cast<float>();
    const Eigen::Matrix4f clip_from_mesh = (clip_from_camera * item.T_camera_mesh.matrix4()).cast<float>();
    glUniformMatrix4fv(g.clip_from_mesh, 1, GL_FALSE, clip_from_mesh.data());
    glUniformMatrix4fv(g.camera_from_mesh, 1, GL_FALSE, camera_from_mesh.data());
    glUniform1i(g.has_texture, mesh.texture ? 1 : 0);
    glBindTexture(GL_TEXTURE_2D, mesh.texture);
    glBindVertexArray(mesh.vao);
    glDrawElements(GL_TRIANGLES, mesh.index_count, GL_UNSIGNED_INT, nullptr);
  }
  glBindVertexArray(0);
  g.readback.resize(static_cast<size_t>(c.width) * c.height * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, c.width, c.height, GL_RGBA, GL_UNSIGNED_BYTE, g.readback.data());
  gl::CheckError("colour render");
  RgbImage image(camera.width, camera.height);
  const Rgb8Pixel background_px{uint8_t(std::lround(bg.x() * 255)), uint8_t(std::lround(bg.y() * 255)),
                                uint8_t(std::lround(bg.z() * 255))};
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const int32_t index = canvas_->CanvasIndexOfImagePixel(u, v);
      if (index < 0) {
        image.at(u, v) = background_px;
        continue;
      }
      const uint8_t* p = &g.readback[static_cast<size_t>(index) * 4];
      image.at(u, v) = {p[0], p[1], p[2]};
    }
  }
  return image;
}

}  // namespace mocap
