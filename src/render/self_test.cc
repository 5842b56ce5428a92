#include "render/self_test.h"

#include <chrono>
#include <cmath>

#include "core/check.h"
#include "render/primitives.h"
#include "render/renderer.h"

namespace mocap {
namespace {

/// Number of pixel centres (integers) strictly inside (lo, hi).
int IntegersInside(double lo, double hi) { return static_cast<int>(std::ceil(hi) - std::floor(lo)) - 1; }

}  // namespace

RenderSelfTestResult RunRenderSelfTest(const RenderContext& context) {
  RenderSelfTestResult result;
  // A 10 cm cube centred 0.5 m ahead: its front face (z = 0.45 m) is the silhouette, a 111.1 px square
  // around the principal point; the edges fall between pixel centres, so the count is exact.
  const PinholeCamera camera{640, 480, 500.0, 500.0, 319.5, 239.5, {}};
  const double half = 0.05, z_front = 0.45, half_px = 500.0 * half / z_front;
  result.expected_pixels = IntegersInside(319.5 - half_px, 319.5 + half_px) * IntegersInside(239.5 - half_px, 239.5 + half_px);
  result.expected_depth_m = z_front;
  Renderer renderer(context);
  const RenderItem item{renderer.Upload(MakeBoxMesh({2 * half, 2 * half, 2 * half})), Rigid3d::FromRvec({0, 0, 0}, {0, 0, 0.5}), 1};
  const RenderOutput out = renderer.Render(camera, std::span(&item, 1));
  for (uint16_t id : out.instance_ids.data) result.pixels += id == 1;
  result.center_depth_m = out.depth_m.at(320, 240);
  PinholeCamera distorted = camera;
  distorted.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633, 0, 0, 0};
  for (uint16_t id : renderer.Render(distorted, std::span(&item, 1)).instance_ids.data) result.distorted_pixels += id == 1;

  const int runs = 20;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < runs; ++i) renderer.Render(camera, std::span(&item, 1));
  result.ms_per_frame = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / runs;

  if (result.pixels != result.expected_pixels)
    result.problem = Str("the cube covers ", result.pixels, " px, expected ", result.expected_pixels,
                         ": the OpenGL driver rasterises wrongly; try --platform surfaceless (Mesa llvmpipe)");
  else if (std::abs(result.center_depth_m - z_front) > 1e-4)
    result.problem = Str("depth at the cube's centre is ", result.center_depth_m, " m, expected ", z_front,
                         " m: float render targets are broken in this driver");
  else if (std::abs(result.distorted_pixels - result.pixels) > result.pixels / 5)
    result.problem = Str("the distorted render covers ", result.distorted_pixels, " px, far from ", result.pixels);
  result.ok = result.problem.empty();
  return result;
}

}  // namespace mocap
