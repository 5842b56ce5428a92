#pragma once
// Test images for the depth PNG codecs (png_gray16_test.cc, png_write_test.cc).
#include <algorithm>
#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <random>

namespace mocap::testing {

/// Depth-like content: smooth ramps, steps, holes (0) and noise, so that libpng's adaptive filter
/// choice (an explicit compression level) uses several filter types.
inline cv::Mat DepthLike(int width, int height, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(-3, 3), coin(0, 40), any(0, 65535);
  cv::Mat image(height, width, CV_16UC1);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      int value = 800 + 3 * u + 2 * v + ((u / 17 + v / 11) % 3) * 400 + noise(rng);
      if (coin(rng) == 0) value = 0;
      if (v % 7 == 3) value = 65535 - u;  // high bytes that wrap under SUB and AVERAGE
      if (u > width / 2 && v % 3 == 0) value = any(rng);  // every byte value, Paeth's ties among them
      image.at<uint16_t>(v, u) = static_cast<uint16_t>(std::clamp(value, 0, 65535));
    }
  return image;
}

}  // namespace mocap::testing
