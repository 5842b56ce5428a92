#pragma once
// Pairs colour and depth images that a device delivers on separate streams (Kinect1: two isochronous
// streams, each image stamped with the 60 MHz counter of its last packet; kinect.md §4 says the two are
// "synchronized if they are within about 120,000 ticks"). Images are matched by unwrapped device ticks.
// Holds at most one waiting image per stream; an image that can no longer find a partner is dropped
// and counted, never delivered alone.
#include <cstdint>
#include <optional>

#include <opencv2/core.hpp>

namespace mocap::capture {

struct StampedImage {
  cv::Mat image;
  uint32_t ticks_raw = 0;
  int64_t ticks = 0;    ///< unwrapped
  int64_t host_ns = 0;  ///< CLOCK_MONOTONIC at receipt
};

struct ImagePair {
  StampedImage depth;
  StampedImage color;
};

class FramePairer {
 public:
  /// Precondition: tolerance_ticks >= 0.
  explicit FramePairer(int64_t tolerance_ticks);

  /// Each returns the completed pair when the new image matches the other stream's waiting image.
  std::optional<ImagePair> AddDepth(StampedImage depth);
  std::optional<ImagePair> AddColor(StampedImage color);

  int64_t depth_unpaired() const { return unpaired_[kDepth]; }
  int64_t color_unpaired() const { return unpaired_[kColor]; }

 private:
  enum Stream { kDepth = 0, kColor = 1 };
  std::optional<ImagePair> Add(Stream stream, StampedImage image);

  int64_t tolerance_ticks_;
  std::optional<StampedImage> waiting_[2];
  int64_t unpaired_[2] = {0, 0};
};

}  // namespace mocap::capture
