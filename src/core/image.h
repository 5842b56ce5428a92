#pragma once
// A minimal owning image for the core (no OpenCV here: conversions to cv::Mat live at the I/O edges).
// Row-major, tightly packed, origin top-left, pixel (u, v) = column u, row v.
#include <cstdint>
#include <vector>

#include "core/check.h"

namespace mocap {

template <typename T>
struct Image {
  int width = 0;
  int height = 0;
  std::vector<T> data;

  Image() = default;
  Image(int w, int h, T fill = T{}) : width(w), height(h), data(static_cast<size_t>(w) * h, fill) {
    MOCAP_CHECK(w >= 0 && h >= 0, "negative image size");
  }
  bool empty() const { return data.empty(); }
  T& at(int u, int v) { return data[static_cast<size_t>(v) * width + u]; }
  const T& at(int u, int v) const { return data[static_cast<size_t>(v) * width + u]; }
  bool contains(int u, int v) const { return u >= 0 && v >= 0 && u < width && v < height; }
};

/// Depth in metres; 0 marks an invalid pixel (no measurement), never filled silently.
using DepthImage = Image<float>;
/// Instance or class labels; 0 is background.
using LabelImage = Image<uint16_t>;

}  // namespace mocap
