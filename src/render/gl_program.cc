#include "render/gl_program.h"

#include <vector>

#include "core/check.h"

namespace mocap::gl {
namespace {

GLuint Compile(GLenum type, const char* source) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    std::vector<char> log(4096);
    glGetShaderInfoLog(shader, static_cast<GLsizei>(log.size()), nullptr, log.data());
    MOCAP_CHECK(false, "shader compile failed: ", log.data());
  }
  return shader;
}

}  // namespace

GLuint LinkProgram(const char* vertex_source, const char* fragment_source) {
  const GLuint vs = Compile(GL_VERTEX_SHADER, vertex_source), fs = Compile(GL_FRAGMENT_SHADER, fragment_source);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    std::vector<char> log(4096);
    glGetProgramInfoLog(program, static_cast<GLsizei>(log.size()), nullptr, log.data());
    MOCAP_CHECK(false, "shader link failed: ", log.data());
  }
  return program;
}

void CheckError(const char* what) {
  const GLenum error = glGetError();
  MOCAP_CHECK(error == GL_NO_ERROR, "OpenGL error 0x", std::hex, error, " in ", what);
}

void Framebuffer::Allocate(int w, int h, GLenum color_format) {
  Release();
  width = w, height = h;
  glGenFramebuffers(1, &fbo);
  glGenRenderbuffers(1, &color);
  glGenRenderbuffers(1, &depth);
  glBindRenderbuffer(GL_RENDERBUFFER, color);
  glRenderbufferStorage(GL_RENDERBUFFER, color_format, w, h);
  glBindRenderbuffer(GL_RENDERBUFFER, depth);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  MOCAP_CHECK(status == GL_FRAMEBUFFER_COMPLETE, "framebuffer ", w, "x", h, " incomplete: 0x", std::hex, status);
  CheckError("framebuffer allocation");
}

void Framebuffer::Release() {
  if (fbo) glDeleteFramebuffers(1, &fbo);
  if (color) glDeleteRenderbuffers(1, &color);
  if (depth) glDeleteRenderbuffers(1, &depth);
  fbo = color = depth = 0;
  width = height = 0;
}

}  // namespace mocap::gl
