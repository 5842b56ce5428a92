#pragma once
// Small RAII helpers over raw OpenGL objects (internal to render/; include render/gl.h first).
#include <string>

#include "render/gl.h"

namespace mocap::gl {

/// Compiles and links a vertex + fragment shader pair; aborts with the driver's log on failure (the
/// shaders are part of the program, so a failure is a bug or a broken driver, not bad input).
GLuint LinkProgram(const char* vertex_source, const char* fragment_source);

/// Aborts with the GL error name when glGetError reports one (`what` names the operation).
void CheckError(const char* what);

/// A colour renderbuffer + depth renderbuffer framebuffer of a given size.
struct Framebuffer {
  GLuint fbo = 0, color = 0, depth = 0;
  int width = 0, height = 0;
  /// (Re)allocates with `color_format` (e.g. GL_R32F); aborts when the framebuffer is incomplete.
  void Allocate(int w, int h, GLenum color_format);
  void Release();
};

}  // namespace mocap::gl
