#pragma once
// An OpenGL context without any window system (DESIGN.md "render"): EGL on the Mesa surfaceless platform
// (CPU rendering through llvmpipe, what CI machines have) or on the EGL device platform (a GPU). All
// rendering goes into framebuffer objects; there is never a window surface, so DISPLAY is irrelevant.
//
// Thread safety: a RenderContext and everything created with it (Renderer, uploaded meshes) belong to the
// thread that created them. Use one RenderContext per thread to render in parallel; contexts do not share
// objects, and distinct contexts may be used concurrently.
#include <memory>
#include <string>

namespace mocap {

enum class EglPlatform {
  kAuto,         ///< a GPU through the device platform when one is found, else Mesa surfaceless
  kSurfaceless,  ///< EGL_MESA_platform_surfaceless (Mesa; llvmpipe on machines without a GPU driver)
  kDevice,       ///< EGL_EXT_platform_device (a GPU driver's EGL device, e.g. NVIDIA)
};

/// "auto", "surfaceless", "device".
std::string ToString(EglPlatform platform);
/// Inverse of ToString; throws InputError naming the accepted values.
EglPlatform EglPlatformFromString(const std::string& name);

struct RenderContextOptions {
  EglPlatform platform = EglPlatform::kAuto;
  /// With kDevice: which EGL device (eglQueryDevicesEXT order); -1 picks the first hardware device.
  int device_index = -1;
  /// Throws InputError on invalid values.
  void check() const;
};

/// What was created, for `mocaplabel doctor` and for provenance in outputs.
struct RenderContextInfo {
  EglPlatform platform = EglPlatform::kAuto;  ///< the platform actually used (never kAuto)
  int device_index = -1;                      ///< EGL device used with kDevice, else -1
  std::string device_extensions;              ///< the EGL device's extensions with kDevice
  std::string egl_vendor, egl_version;
  std::string gl_vendor, gl_renderer, gl_version;
  bool software = false;  ///< true for llvmpipe / softpipe (CPU rendering)
};

/// An EGL display plus a current OpenGL 3.3 core context with no surface. Created or throws; releases
/// everything in its destructor. Not copyable or movable (GL objects refer to it).
class RenderContext {
 public:
  /// Creates the context and makes it current on the calling thread. Throws std::runtime_error naming
  /// what was tried, which EGL extension or call failed, and which Debian packages provide it.
  static std::unique_ptr<RenderContext> Create(const RenderContextOptions& options = {});
  ~RenderContext();
  RenderContext(const RenderContext&) = delete;
  RenderContext& operator=(const RenderContext&) = delete;

  const RenderContextInfo& info() const { return info_; }
  /// Makes the context current on the calling thread (after moving ownership to another thread; the
  /// previous thread must not use it any more).
  void MakeCurrent() const;

 private:
  RenderContext() = default;
  void FillInfo();
  struct Egl;
  std::unique_ptr<Egl> egl_;
  RenderContextInfo info_;
};

}  // namespace mocap
