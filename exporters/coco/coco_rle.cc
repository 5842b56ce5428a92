#include "exporters/coco/coco_rle.h"

#include <algorithm>
#include <limits>

#include "core/check.h"

namespace mocap::exporters {
namespace {

/// Collects the runs of 1s of a mask in column-major order into maskApi.c rleEncode's counts. A run that
/// starts where the previous one ended (a column's run reaching the bottom row, the next column's run
/// starting at the top row) continues it, as rleEncode's single pass over the flattened mask would.
class RunCounter {
 public:
  void Ones(uint64_t start, uint64_t length) {
    if (!counts_.empty() && start == end_) {
      counts_.back() += Count(length);
    } else {
      counts_.push_back(Count(start - end_));  // the 0s before (0 when the mask starts with a 1)
      counts_.push_back(Count(length));
    }
    end_ = start + length;
  }

  /// rleEncode always ends with the run in progress: the trailing 0s, or the whole image when no pixel
  /// is set (a single count, 0 for a 0x0 mask); nothing more when the last pixel is set.
  std::vector<uint32_t> Finish(uint64_t area) && {
    if (counts_.empty() || area > end_) counts_.push_back(Count(area - end_));
    return std::move(counts_);
  }

 private:
  static uint32_t Count(uint64_t n) {
    MOCAP_CHECK(n <= std::numeric_limits<uint32_t>::max(), "mask of ", n, " pixels: COCO counts are 32-bit");
    return static_cast<uint32_t>(n);
  }
  std::vector<uint32_t> counts_;
  uint64_t end_ = 0;  ///< position after the last run of 1s
};

/// Encodes the part of `rect` inside the image; `data` is the rect's top-left byte, rows `row_step` apart.
CocoRle EncodeRect(const uint8_t* data, size_t row_step, const PixelRect& rect, int image_width, int image_height) {
  MOCAP_CHECK(image_width >= 0 && image_height >= 0, "negative image size");
  const int u0 = std::max(rect.x, 0), u1 = std::min(rect.x + rect.width, image_width);
  const int v0 = std::max(rect.y, 0), v1 = std::min(rect.y + rect.height, image_height);
  RunCounter runs;
  // Column by column (the crop is row-major, so this walks it with a stride; crops are small enough to
  // stay in cache, and building the transposed full image would cost far more).
  for (int u = u0; u < u1; ++u) {
    const uint8_t* column = data + (u - rect.x);
    const uint64_t column_start = static_cast<uint64_t>(u) * static_cast<uint64_t>(image_height);
    int v = v0;
    while (v < v1) {
      while (v < v1 && column[static_cast<size_t>(v - rect.y) * row_step] == 0) ++v;
      const int first = v;
      while (v < v1 && column[static_cast<size_t>(v - rect.y) * row_step] != 0) ++v;
      if (v > first) runs.Ones(column_start + static_cast<uint64_t>(first), static_cast<uint64_t>(v - first));
    }
  }
  const uint64_t area = static_cast<uint64_t>(image_width) * static_cast<uint64_t>(image_height);
  return {image_height, image_width, std::move(runs).Finish(area)};
}

}  // namespace

CocoRle EncodeCocoRle(const cv::Mat& mask) {
  MOCAP_CHECK(mask.type() == CV_8UC1, "COCO RLE of a mask that is not CV_8UC1");
  return EncodeRect(mask.ptr<uint8_t>(), mask.step[0], PixelRect{0, 0, mask.cols, mask.rows}, mask.cols, mask.rows);
}

CocoRle EncodeCocoRle(const std::vector<uint8_t>& crop, const PixelRect& rect, int image_width, int image_height) {
  if (rect.empty()) return EncodeRect(nullptr, 0, PixelRect{}, image_width, image_height);
  MOCAP_CHECK(crop.size() == static_cast<size_t>(rect.width) * static_cast<size_t>(rect.height), "a ", crop.size(),
              "-byte crop for a ", rect.width, "x", rect.height, " rect");
  return EncodeRect(crop.data(), static_cast<size_t>(rect.width), rect, image_width, image_height);
}

std::string CocoRleString(const std::vector<uint32_t>& counts) {
  std::string text;
  text.reserve(counts.size() * 2);
  for (size_t i = 0; i < counts.size(); ++i) {
    int64_t x = counts[i];
    // maskApi.c: `if(i>2) x-=cnts[i-2]` -- the third count is written whole, deltas start at the fourth.
    if (i > 2) x -= counts[i - 2];
    bool more = true;
    while (more) {
      int64_t group = x & 0x1f;
      x >>= 5;  // arithmetic shift (C++20): negative deltas end in -1
      // Stop once the rest is pure sign extension of this group's top bit (0x10).
      more = (group & 0x10) != 0 ? x != -1 : x != 0;
      if (more) group |= 0x20;
      text.push_back(static_cast<char>(48 + group));
    }
  }
  return text;
}

std::vector<uint32_t> CocoRleCountsFromString(std::string_view text, const std::string& where) {
  std::vector<uint32_t> counts;
  size_t p = 0;
  while (p < text.size()) {
    int64_t x = 0;
    int shift = 0;
    bool more = true;
    while (more) {
      if (p >= text.size()) throw InputError(where, "COCO RLE string ends inside a count");
      const int group = text[p++] - 48;
      if (group < 0 || group > 63) throw InputError(where, Str("COCO RLE string has a character outside '0'..'o' at ", p - 1));
      if (shift > 55) throw InputError(where, Str("COCO RLE count longer than 12 characters ending at ", p - 1));
      x |= static_cast<int64_t>(group & 0x1f) << shift;
      shift += 5;
      more = (group & 0x20) != 0;
      if (!more && (group & 0x10) != 0) x |= static_cast<int64_t>(~uint64_t{0} << shift);  // sign
    }
    if (counts.size() > 2) x += counts[counts.size() - 2];
    if (x < 0 || x > std::numeric_limits<uint32_t>::max())
      throw InputError(where, Str("COCO RLE count ", counts.size(), " is ", x, ", outside 0..2^32-1"));
    counts.push_back(static_cast<uint32_t>(x));
  }
  return counts;
}

int64_t CocoRleArea(const CocoRle& rle) {
  int64_t area = 0;
  for (size_t i = 1; i < rle.counts.size(); i += 2) area += rle.counts[i];
  return area;
}

std::array<double, 4> CocoRleBox(const CocoRle& rle) {
  const uint64_t h = static_cast<uint64_t>(rle.height);
  uint64_t x_min = std::numeric_limits<uint64_t>::max(), x_max = 0, y_min = x_min, y_max = 0;
  uint64_t position = 0;
  for (size_t i = 0; i < rle.counts.size(); ++i) {
    const uint64_t start = position;
    position += rle.counts[i];
    if (i % 2 == 0 || rle.counts[i] == 0) continue;  // a run of 0s
    const uint64_t last = position - 1;
    const uint64_t x_first = start / h, x_last = last / h;
    x_min = std::min(x_min, x_first), x_max = std::max(x_max, x_last);
    // A run that wraps into the next column covers the bottom row of one and the top row of the next
    // (maskApi.c rleToBbox: `if(xp<x) { ys=0; ye=h-1; }`).
    const bool wraps = x_last > x_first;
    y_min = std::min(y_min, wraps ? 0 : start % h), y_max = std::max(y_max, wraps ? h - 1 : last % h);
  }
  if (x_min > x_max) return {0, 0, 0, 0};
  return {static_cast<double>(x_min), static_cast<double>(y_min), static_cast<double>(x_max - x_min + 1),
          static_cast<double>(y_max - y_min + 1)};
}

}  // namespace mocap::exporters
