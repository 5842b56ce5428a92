// `mocaplabel doctor`: can this machine render headless? Reports the EGL platform, vendor and version,
// the OpenGL renderer, and renders a test cube with a known pixel count.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli/parse_args.h"
#include "cli/commands.h"
#include "core/check.h"
#include "render/render_context.h"
#include "render/self_test.h"

namespace mocap::cli {
namespace {

/// Environment variables that change which EGL / GL driver is used.
nlohmann::json RelevantEnvironment() {
  nlohmann::json env = nlohmann::json::object();
  for (const char* name : {"DISPLAY", "EGL_PLATFORM", "__EGL_VENDOR_LIBRARY_FILENAMES", "__EGL_VENDOR_LIBRARY_DIRS",
                           "LIBGL_ALWAYS_SOFTWARE", "GALLIUM_DRIVER", "LP_NUM_THREADS", "MESA_LOADER_DRIVER_OVERRIDE"})
    if (const char* value = std::getenv(name)) env[name] = value;
  nlohmann::json vendors = nlohmann::json::array();
  for (const char* dir : {"/usr/share/glvnd/egl_vendor.d", "/etc/glvnd/egl_vendor.d"}) {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) vendors.push_back(entry.path().string());
  }
  return {{"environment", env}, {"egl_vendor_files", vendors}};
}

void PrintText(const nlohmann::json& report) {
  const auto& setup = report["setup"];
  std::printf("EGL vendor files: %s\n", setup["egl_vendor_files"].dump().c_str());
  if (!setup["environment"].empty()) std::printf("environment:      %s\n", setup["environment"].dump().c_str());
  if (report.contains("error")) {
    std::printf("context:          FAILED\n  %s\n", report["error"].get<std::string>().c_str());
    return;
  }
  const auto& c = report["context"];
  std::printf("EGL platform:     %s%s\n", c["platform"].get<std::string>().c_str(), c["software"].get<bool>() ? " (CPU rendering)" : " (GPU)");
  std::printf("EGL:              %s, version %s\n", c["egl_vendor"].get<std::string>().c_str(), c["egl_version"].get<std::string>().c_str());
  std::printf("OpenGL:           %s | %s | %s\n", c["gl_vendor"].get<std::string>().c_str(),
              c["gl_renderer"].get<std::string>().c_str(), c["gl_version"].get<std::string>().c_str());
  const auto& t = report["render_test"];
  std::printf("test render:      %d px (expected %d), depth %.4f m (expected %.4f), distorted %d px, %.2f ms/frame\n",
              t["pixels"].get<int>(), t["expected_pixels"].get<int>(), t["center_depth_m"].get<double>(),
              t["expected_depth_m"].get<double>(), t["distorted_pixels"].get<int>(), t["ms_per_frame"].get<double>());
  std::printf("%s\n", report["ok"].get<bool>() ? "OK: headless rendering works" : ("PROBLEM: " + t["problem"].get<std::string>()).c_str());
}

}  // namespace

int RunDoctor(int argc, char** argv) {
  CLI::App app{"Check headless (EGL) rendering: platform, driver, and a test render", "mocaplabel doctor"};
  bool json = false;
  std::string platform = "auto";
  int device = -1;
  app.add_flag("--json", json, "print one JSON document");
  app.add_option("--platform", platform, "EGL platform: auto, surfaceless (Mesa, CPU) or device (GPU)");
  app.add_option("--device", device, "EGL device index with --platform device (default: first GPU)");
  MOCAP_PARSE(app, argc, argv);

  RenderContextOptions options{.platform = EglPlatformFromString(platform), .device_index = device};
  nlohmann::json report{{"setup", RelevantEnvironment()}, {"ok", false}};
  std::unique_ptr<RenderContext> context;
  options.check();  // bad flags are the user's error (exit 1 with one line), not a rendering problem
  try {
    context = RenderContext::Create(options);
  } catch (const std::runtime_error& e) {
    report["error"] = e.what();
  }
  if (context) {
    const RenderContextInfo& info = context->info();
    report["context"] = {{"platform", ToString(info.platform)}, {"device_index", info.device_index},
                         {"software", info.software}, {"egl_vendor", info.egl_vendor}, {"egl_version", info.egl_version},
                         {"gl_vendor", info.gl_vendor}, {"gl_renderer", info.gl_renderer}, {"gl_version", info.gl_version}};
    const RenderSelfTestResult test = RunRenderSelfTest(*context);
    report["render_test"] = {{"ok", test.ok}, {"pixels", test.pixels}, {"expected_pixels", test.expected_pixels},
                             {"center_depth_m", test.center_depth_m}, {"expected_depth_m", test.expected_depth_m},
                             {"distorted_pixels", test.distorted_pixels}, {"ms_per_frame", test.ms_per_frame},
                             {"problem", test.problem}};
    report["ok"] = test.ok;
  }
  if (json) std::printf("%s\n", report.dump(2).c_str());
  else PrintText(report);
  return report["ok"].get<bool>() ? 0 : 1;
}

}  // namespace mocap::cli
