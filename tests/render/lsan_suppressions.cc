// Mesa's EGL/llvmpipe and LLVM keep process-lifetime allocations (driver screens, JIT caches) that
// LeakSanitizer reports at exit although nothing leaks per frame. The sanitizer run reads these
// suppressions through LeakSanitizer's documented hook; they name only the driver libraries.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libLLVM\n"
         "leak:swrast_dri.so\n"
         "leak:libgallium\n"
         "leak:libEGL_mesa.so\n"
         "leak:libglapi.so\n"
         "leak:libdrm\n";
}
