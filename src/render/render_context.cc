#include "render/render_context.h"

#define EGL_EGLEXT_PROTOTYPES
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "render/gl.h"

#include <cstring>
#include <stdexcept>
#include <vector>

#include "core/check.h"

namespace mocap {
namespace {

constexpr const char* kInstallHint =
    "CPU rendering needs Mesa's EGL and llvmpipe (Debian: apt-get install libegl1 libegl-mesa0 "
    "libgl1-mesa-dri); a GPU needs its driver's EGL library (NVIDIA: libegl-nvidia0 from the driver); "
    "run `mocaplabel doctor` to check";

bool HasExtension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const size_t n = std::strlen(name);
  for (const char* p = std::strstr(list, name); p != nullptr; p = std::strstr(p + n, name)) {
    const bool starts = p == list || p[-1] == ' ';
    const bool ends = p[n] == '\0' || p[n] == ' ';
    if (starts && ends) return true;
  }
  return false;
}

std::string EglErrorName(EGLint error) {
  switch (error) {
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: return Str("EGL error 0x", std::hex, error);
  }
}

/// A platform that could not be opened; the message says why.
struct PlatformFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <typename Fn>
Fn LoadEgl(const char* name) {
  auto fn = reinterpret_cast<Fn>(eglGetProcAddress(name));
  if (fn == nullptr) throw PlatformFailure(Str("the EGL library does not provide ", name));
  return fn;
}

EGLDisplay OpenSurfaceless() {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!HasExtension(client, "EGL_MESA_platform_surfaceless"))
    throw PlatformFailure("EGL client extension EGL_MESA_platform_surfaceless is missing (Mesa's libegl-mesa0 not installed?)");
  auto get_display = LoadEgl<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
  EGLDisplay display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY) throw PlatformFailure("eglGetPlatformDisplayEXT(surfaceless) returned no display");
  return display;
}

struct DeviceList {
  std::vector<EGLDeviceEXT> devices;
  std::vector<std::string> extensions;
};

DeviceList QueryDevices() {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  for (const char* ext : {"EGL_EXT_platform_device", "EGL_EXT_device_enumeration", "EGL_EXT_device_query"})
    if (!HasExtension(client, ext)) throw PlatformFailure(Str("EGL client extension ", ext, " is missing"));
  auto query_devices = LoadEgl<PFNEGLQUERYDEVICESEXTPROC>("eglQueryDevicesEXT");
  auto query_string = LoadEgl<PFNEGLQUERYDEVICESTRINGEXTPROC>("eglQueryDeviceStringEXT");
  DeviceList list;
  EGLint count = 0;
  if (!query_devices(0, nullptr, &count) || count <= 0) throw PlatformFailure("eglQueryDevicesEXT found no EGL device");
  list.devices.resize(static_cast<size_t>(count));
  query_devices(count, list.devices.data(), &count);
  list.devices.resize(static_cast<size_t>(count));
  for (EGLDeviceEXT device : list.devices) {
    const char* ext = query_string(device, EGL_EXTENSIONS);
    list.extensions.emplace_back(ext ? ext : "");
  }
  return list;
}

EGLDisplay OpenDevice(int requested_index, bool hardware_only, RenderContextInfo& info) {
  const DeviceList list = QueryDevices();
  int index = requested_index;
  if (index < 0) {
    for (size_t i = 0; i < list.devices.size() && index < 0; ++i)
      if (!HasExtension(list.extensions[i].c_str(), "EGL_MESA_device_software")) index = static_cast<int>(i);
    if (index < 0 && hardware_only)
      throw PlatformFailure(Str("the ", list.devices.size(), " EGL device(s) found are all software (no GPU driver's EGL)"));
    if (index < 0) index = 0;
  }
  if (index >= static_cast<int>(list.devices.size()))
    throw PlatformFailure(Str("EGL device ", index, " requested but only ", list.devices.size(), " found"));
  auto get_display = LoadEgl<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
  EGLDisplay display = get_display(EGL_PLATFORM_DEVICE_EXT, list.devices[static_cast<size_t>(index)], nullptr);
  if (display == EGL_NO_DISPLAY) throw PlatformFailure(Str("eglGetPlatformDisplayEXT(device ", index, ") returned no display"));
  info.device_index = index;
  info.device_extensions = list.extensions[static_cast<size_t>(index)];
  return display;
}

}  // namespace

struct RenderContext::Egl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  EGLSurface surface = EGL_NO_SURFACE;  // a 1x1 pbuffer only where surfaceless contexts are unsupported

  ~Egl() {
    if (display == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (surface != EGL_NO_SURFACE) eglDestroySurface(display, surface);
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
    eglTerminate(display);
  }

  /// Initialises `display` and creates a current OpenGL 3.3 core context on it.
  void Start(EGLDisplay d) {
    display = d;
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) {
      display = EGL_NO_DISPLAY;
      throw PlatformFailure(Str("eglInitialize failed: ", EglErrorName(eglGetError())));
    }
    if (!eglBindAPI(EGL_OPENGL_API)) throw PlatformFailure("eglBindAPI(EGL_OPENGL_API) failed: no desktop OpenGL");
    const char* ext = eglQueryString(display, EGL_EXTENSIONS);
    if (!HasExtension(ext, "EGL_KHR_create_context"))
      throw PlatformFailure("EGL display extension EGL_KHR_create_context is missing (needed for a core profile)");
    EGLConfig config = EGL_NO_CONFIG_KHR;
    const bool need_surface = !HasExtension(ext, "EGL_KHR_surfaceless_context");
    if (need_surface || !HasExtension(ext, "EGL_KHR_no_config_context")) config = ChooseConfig();
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    context = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
    if (context == EGL_NO_CONTEXT)
      throw PlatformFailure(Str("eglCreateContext(OpenGL 3.3 core) failed: ", EglErrorName(eglGetError())));
    if (need_surface) {
      const EGLint pbuffer[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
      surface = eglCreatePbufferSurface(display, config, pbuffer);
      if (surface == EGL_NO_SURFACE) throw PlatformFailure("no EGL_KHR_surfaceless_context and no pbuffer surface");
    }
    if (!eglMakeCurrent(display, surface, surface, context))
      throw PlatformFailure(Str("eglMakeCurrent failed: ", EglErrorName(eglGetError())));
  }

  EGLConfig ChooseConfig() const {
    const EGLint wanted[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint count = 0;
    if (!eglChooseConfig(display, wanted, &config, 1, &count) || count < 1)
      throw PlatformFailure("eglChooseConfig found no OpenGL pbuffer config");
    return config;
  }
};

std::string ToString(EglPlatform platform) {
  switch (platform) {
    case EglPlatform::kAuto: return "auto";
    case EglPlatform::kSurfaceless: return "surfaceless";
    case EglPlatform::kDevice: return "device";
  }
  return "?";
}

EglPlatform EglPlatformFromString(const std::string& name) {
  for (EglPlatform p : {EglPlatform::kAuto, EglPlatform::kSurfaceless, EglPlatform::kDevice})
    if (ToString(p) == name) return p;
  throw InputError("render platform", Str("'", name, "' is not one of auto, surfaceless, device"));
}

void RenderContextOptions::check() const {
  if (device_index < -1) throw InputError("render options", Str("device_index ", device_index, " must be >= -1"));
  if (device_index >= 0 && platform != EglPlatform::kDevice)
    throw InputError("render options", "device_index is only meaningful with platform 'device'");
}

std::unique_ptr<RenderContext> RenderContext::Create(const RenderContextOptions& options) {
  options.check();
  std::vector<EglPlatform> tries;
  if (options.platform == EglPlatform::kAuto) tries = {EglPlatform::kDevice, EglPlatform::kSurfaceless};
  else tries = {options.platform};
  std::string failures;
  for (EglPlatform platform : tries) {
    std::unique_ptr<RenderContext> ctx(new RenderContext());
    ctx->egl_ = std::make_unique<Egl>();
    ctx->info_.platform = platform;
    try {
      const bool hardware_only = options.platform == EglPlatform::kAuto;
      ctx->egl_->Start(platform == EglPlatform::kDevice ? OpenDevice(options.device_index, hardware_only, ctx->info_)
                                                        : OpenSurfaceless());
    } catch (const PlatformFailure& e) {
      failures += Str(failures.empty() ? "" : "; ", ToString(platform), ": ", e.what());
      continue;
    }
    ctx->FillInfo();
    return ctx;
  }
  throw std::runtime_error(Str("no headless OpenGL context (tried ", failures, "). ", kInstallHint));
}

void RenderContext::FillInfo() {
  auto str = [](const char* s) { return std::string(s ? s : ""); };
  info_.egl_vendor = str(eglQueryString(egl_->display, EGL_VENDOR));
  info_.egl_version = str(eglQueryString(egl_->display, EGL_VERSION));
  info_.gl_vendor = str(reinterpret_cast<const char*>(glGetString(GL_VENDOR)));
  info_.gl_renderer = str(reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
  info_.gl_version = str(reinterpret_cast<const char*>(glGetString(GL_VERSION)));
  info_.software = info_.gl_renderer.find("llvmpipe") != std::string::npos ||
                   info_.gl_renderer.find("softpipe") != std::string::npos ||
                   HasExtension(info_.device_extensions.c_str(), "EGL_MESA_device_software");
}

RenderContext::~RenderContext() = default;

void RenderContext::MakeCurrent() const {
  MOCAP_CHECK(eglMakeCurrent(egl_->display, egl_->surface, egl_->surface, egl_->context), "eglMakeCurrent failed: ",
              EglErrorName(eglGetError()));
}

}  // namespace mocap
