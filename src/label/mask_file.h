#pragma once
// One 8-bit PNG per object and frame carries all three masks (object_labels.h) as bits, cropped to the
// in-image bounding box of the object's amodal mask; labels.jsonl records that box as `mask_rect`
// (docs/labels.md). The masks are not nested (a pixel hidden in the model z-buffer can still agree with
// the measured depth), hence bits rather than levels.
#include <filesystem>
#include <opencv2/core/mat.hpp>

#include "label/label_png.h"
#include "label/object_labels.h"

namespace mocap {

inline constexpr uint8_t kMaskBitAmodal = 1;           ///< the object rendered alone (BOP `mask`)
inline constexpr uint8_t kMaskBitVisibleModel = 2;     ///< nearest in the model z-buffer
inline constexpr uint8_t kMaskBitVisibleMeasured = 4;  ///< BOP19 `mask_visib` against the measured depth

/// The packed masks of one object: `bits` (CV_8UC1, rect.height x rect.width) over `rect` (image pixels,
/// x, y = top-left pixel, width, height = the image's size; not BOP's box convention). Both empty when
/// the object covers no pixel of the image.
struct PackedMasks {
  PixelRect rect;
  cv::Mat bits;
};

/// Packs `masks` over the in-image box of masks.amodal (every visible pixel is an amodal pixel).
PackedMasks PackMasks(const ObjectMasks& masks);

/// The exact inverse of PackMasks. `has_measured`: whether visible_measured is present (labels.jsonl
/// `visib_source` is "measured_depth"); without it visible_measured stays empty. Throws InputError when
/// `bits` does not have rect's size or holds values other than the three bits.
ObjectMasks UnpackMasks(const cv::Mat& bits, const PixelRect& rect, bool has_measured);

/// Reads a mask file written by the labeller; `rect` is its record's `mask_rect`. Throws InputError for a
/// missing or unreadable file or one that does not match `rect`.
ObjectMasks ReadMaskFile(const std::filesystem::path& png, const PixelRect& rect, bool has_measured);

}  // namespace mocap
