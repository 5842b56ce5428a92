#include "render/render_context.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "core/check.h"
#include "render/self_test.h"

namespace mocap {
namespace {

TEST(RenderContext, AutoCreatesWithoutDisplay) {
  unsetenv("DISPLAY");
  unsetenv("WAYLAND_DISPLAY");
  const auto context = RenderContext::Create();
  const RenderContextInfo& info = context->info();
  EXPECT_NE(info.platform, EglPlatform::kAuto);
  EXPECT_FALSE(info.egl_version.empty());
  EXPECT_NE(info.gl_version.find("3."), info.gl_version.find("4.")) << "a 3.x or 4.x context: " << info.gl_version;
  EXPECT_FALSE(info.gl_renderer.empty());
}

TEST(RenderContext, SurfacelessIsMesa) {
  const auto context = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
  EXPECT_EQ(context->info().platform, EglPlatform::kSurfaceless);
  EXPECT_NE(context->info().egl_vendor.find("Mesa"), std::string::npos) << context->info().egl_vendor;
}

TEST(RenderContext, TwoContextsCoexist) {
  const auto a = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
  const auto b = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
  a->MakeCurrent();
  b->MakeCurrent();
  SUCCEED();
}

TEST(RenderContext, MissingDeviceIsAClearError) {
  try {
    RenderContext::Create({.platform = EglPlatform::kDevice, .device_index = 99});
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("device"), std::string::npos) << what;
    EXPECT_NE(what.find("apt-get install"), std::string::npos) << "says what to install: " << what;
  }
}

TEST(RenderContext, PlatformNamesRoundTrip) {
  for (EglPlatform p : {EglPlatform::kAuto, EglPlatform::kSurfaceless, EglPlatform::kDevice})
    EXPECT_EQ(EglPlatformFromString(ToString(p)), p);
  EXPECT_THROW(EglPlatformFromString("x11"), InputError);
  EXPECT_THROW(RenderContext::Create({.platform = EglPlatform::kAuto, .device_index = 0}), InputError);
}

TEST(RenderSelfTest, CubeHasThePredictedSilhouette) {
  const auto context = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
  const RenderSelfTestResult result = RunRenderSelfTest(*context);
  EXPECT_TRUE(result.ok) << result.problem;
  EXPECT_EQ(result.pixels, 112 * 112);  // 111.1 px square around (319.5, 239.5): centres 264..375
  EXPECT_EQ(result.expected_pixels, 112 * 112);
  EXPECT_NEAR(result.center_depth_m, 0.45, 1e-6);
  EXPECT_GT(result.ms_per_frame, 0.0);
}

}  // namespace
}  // namespace mocap
