#pragma once
// ASCII pictures of small images for the label tests: one string per row, one character per pixel.
#include <string>
#include <vector>

#include "core/camera.h"

namespace mocap::test {

using Picture = std::vector<std::string>;

/// A pinhole camera the size of the picture, f = 525 px, centred.
inline PinholeCamera CameraOf(const Picture& p) {
  const int w = static_cast<int>(p[0].size()), h = static_cast<int>(p.size());
  return {w, h, 525.0, 525.0, (w - 1) / 2.0, (h - 1) / 2.0, {}};
}

/// The picture as text, one row per line (for failure messages).
inline std::string Lines(const Picture& p) {
  std::string s;
  for (const std::string& row : p) s += row + "\n";
  return s;
}

}  // namespace mocap::test
