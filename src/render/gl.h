#pragma once
// The one place that includes OpenGL: desktop OpenGL 3.3 core through glvnd's libOpenGL (no loader needed,
// libOpenGL exports the core entry points). Included by render/*.cc only, never by public headers.
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>
