#include "label/mask_file.h"

#include <algorithm>
#include <opencv2/imgcodecs.hpp>

#include "core/check.h"

namespace mocap {
namespace {

/// In-image box of the set pixels of a rect-sized mask (empty when none is set).
PixelRect SetBox(const std::vector<uint8_t>& mask, const PixelRect& rect) {
  const PixelBox b = MaskBox(mask, rect);
  if (b[0] < 0) return {};
  return {b[0], b[1], b[2] + 1, b[3] + 1};
}

void CopyBit(const std::vector<uint8_t>& mask, const PixelRect& from, const PixelRect& to, uint8_t bit, cv::Mat& bits) {
  if (mask.empty()) return;
  for (int v = 0; v < to.height; ++v) {
    const uint8_t* src = mask.data() + static_cast<size_t>(v + to.y - from.y) * from.width + (to.x - from.x);
    uint8_t* dst = bits.ptr<uint8_t>(v);
    for (int u = 0; u < to.width; ++u) dst[u] |= src[u] ? bit : 0;
  }
}

}  // namespace

PackedMasks PackMasks(const ObjectMasks& masks) {
  PackedMasks packed;
  packed.rect = SetBox(masks.amodal, masks.rect);
  if (packed.rect.empty()) return packed;
  packed.bits = cv::Mat::zeros(packed.rect.height, packed.rect.width, CV_8UC1);
  CopyBit(masks.amodal, masks.rect, packed.rect, kMaskBitAmodal, packed.bits);
  CopyBit(masks.visible_model, masks.rect, packed.rect, kMaskBitVisibleModel, packed.bits);
  CopyBit(masks.visible_measured, masks.rect, packed.rect, kMaskBitVisibleMeasured, packed.bits);
  return packed;
}

cv::Mat StackMasks(const std::vector<PackedMasks*>& packed) {
  int width = 0, height = 0;
  for (PackedMasks* p : packed) {
    if (p->bits.empty()) continue;
    p->file_row = height;
    height += p->bits.rows, width = std::max(width, p->bits.cols);
  }
  if (height == 0) return {};
  cv::Mat stacked = cv::Mat::zeros(height, width, CV_8UC1);
  for (const PackedMasks* p : packed)
    if (!p->bits.empty()) p->bits.copyTo(stacked(cv::Rect(0, p->file_row, p->bits.cols, p->bits.rows)));
  return stacked;
}

ObjectMasks UnpackMasks(const cv::Mat& bits, const PixelRect& rect, bool has_measured) {
  if (bits.type() != CV_8UC1 || bits.cols != rect.width || bits.rows != rect.height)
    throw InputError("mask file", Str("expected an 8-bit ", rect.width, "x", rect.height, " image (mask_rect), got ",
                                      bits.cols, "x", bits.rows, " of OpenCV type ", bits.type()));
  ObjectMasks masks;
  masks.rect = rect;
  const size_t n = static_cast<size_t>(rect.width) * rect.height;
  masks.amodal.assign(n, 0);
  masks.visible_model.assign(n, 0);
  if (has_measured) masks.visible_measured.assign(n, 0);
  constexpr uint8_t kAll = kMaskBitAmodal | kMaskBitVisibleModel | kMaskBitVisibleMeasured;
  for (int v = 0; v < rect.height; ++v) {
    const uint8_t* row = bits.ptr<uint8_t>(v);
    for (int u = 0; u < rect.width; ++u) {
      const uint8_t b = row[u];
      if (b & ~kAll || (b != 0 && !(b & kMaskBitAmodal)))
        throw InputError("mask file", Str("pixel (", rect.x + u, ", ", rect.y + v, ") holds ", int(b),
                                          ": not a labeller mask file (bits 1, 2, 4; 2 and 4 only with 1)"));
      const size_t i = static_cast<size_t>(v) * rect.width + u;
      masks.amodal[i] = b & kMaskBitAmodal ? 1 : 0;
      masks.visible_model[i] = b & kMaskBitVisibleModel ? 1 : 0;
      if (has_measured) masks.visible_measured[i] = b & kMaskBitVisibleMeasured ? 1 : 0;
    }
  }
  return masks;
}

ObjectMasks MasksFromFile(const cv::Mat& file, const std::string& where, const PixelRect& rect, bool has_measured,
                          int first_row) {
  if (first_row < 0 || rect.width < 0 || rect.height < 0 || file.cols < rect.width || file.rows < first_row + rect.height)
    throw InputError(where, Str("a ", file.cols, "x", file.rows, " mask file cannot hold a ", rect.width, "x",
                                rect.height, " crop at row ", first_row, " (mask_rect / mask_row)"));
  try {
    return UnpackMasks(file(cv::Rect(0, first_row, rect.width, rect.height)), rect, has_measured);
  } catch (const InputError& e) {
    throw InputError(where, e.what());
  }
}

ObjectMasks ReadMaskFile(const std::filesystem::path& png, const PixelRect& rect, bool has_measured, int first_row) {
  const cv::Mat file = cv::imread(png.string(), cv::IMREAD_UNCHANGED);
  if (file.empty()) throw InputError(png.string(), "missing or not a readable PNG");
  return MasksFromFile(file, png.string(), rect, has_measured, first_row);
}

}  // namespace mocap
