#pragma once
// A render self-test with a known answer, for `mocaplabel doctor`: a cube straight ahead of a camera,
// whose silhouette pixel count and depth follow from the pinhole model alone.
#include <string>

#include "render/render_context.h"

namespace mocap {

struct RenderSelfTestResult {
  bool ok = false;
  int pixels = 0, expected_pixels = 0;          ///< silhouette pixel count, rendered and predicted
  double center_depth_m = 0, expected_depth_m = 0;
  int distorted_pixels = 0;                     ///< same cube through a distorted camera (>0 expected)
  double ms_per_frame = 0;                      ///< 640x480, id + depth + one layer, mean of a short run
  std::string problem;                          ///< empty when ok
};

/// Renders the test cube with `context` (current on this thread) and checks the result.
RenderSelfTestResult RunRenderSelfTest(const RenderContext& context);

}  // namespace mocap
