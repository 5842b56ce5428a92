#pragma once
// All three masks (object_labels.h) of an object as bits, cropped to the in-image bounding box of its
// amodal mask; one 8-bit PNG per frame holds the crops of all its objects stacked top to bottom, each
// left-aligned (fewer files per frame: creating files is much of the output's cost on ext4).
// labels.jsonl records each crop's box as `mask_rect` and its first row in the file as `mask_row`
// (docs/labels.md). Under BOP19's visibility rule the masks are not nested (a pixel hidden in the model
// z-buffer can still agree with the measured depth), hence bits rather than levels.
#include <filesystem>
#include <string>
#include <opencv2/core/mat.hpp>

#include "label/label_png.h"
#include "label/object_labels.h"

namespace mocap {

inline constexpr uint8_t kMaskBitAmodal = 1;           ///< the object rendered alone (BOP `mask`)
inline constexpr uint8_t kMaskBitVisibleModel = 2;     ///< nearest in the model z-buffer
inline constexpr uint8_t kMaskBitVisibleMeasured = 4;  ///< visible by the measured depth (VisibilityOptions::rule)

/// The packed masks of one object: `bits` (CV_8UC1, rect.height x rect.width) over `rect` (image pixels,
/// x, y = top-left pixel, width, height = the image's size; not BOP's box convention). Both empty when
/// the object covers no pixel of the image.
struct PackedMasks {
  PixelRect rect;
  cv::Mat bits;
  int file_row = 0;  ///< first row of `bits` in the frame's mask file (StackMasks)
};

/// Packs `masks` over the in-image box of masks.amodal (every visible pixel is an amodal pixel).
PackedMasks PackMasks(const ObjectMasks& masks);

/// Assigns each non-empty entry its `file_row` (in order) and returns the frame's mask image: the crops
/// stacked, left-aligned, zero to the right of narrower ones. Empty when no entry covers a pixel.
cv::Mat StackMasks(const std::vector<PackedMasks*>& packed);

/// The exact inverse of PackMasks. `has_measured`: whether visible_measured is present (labels.jsonl
/// `visib_source` is "measured_depth"); without it visible_measured stays empty. Throws InputError when
/// `bits` does not have rect's size or holds values other than the three bits.
ObjectMasks UnpackMasks(const cv::Mat& bits, const PixelRect& rect, bool has_measured);

/// One object's masks from a frame's mask file already decoded (`file`, named `where` in errors), so a
/// frame's objects share one decode. Throws InputError when the file's size cannot hold the crop.
ObjectMasks MasksFromFile(const cv::Mat& file, const std::string& where, const PixelRect& rect, bool has_measured,
                          int first_row = 0);

/// Reads one object's masks from a frame's mask file; `rect` and `first_row` are its record's `mask_rect`
/// and `mask_row`. Throws InputError for a missing or unreadable file or one whose size cannot hold them.
ObjectMasks ReadMaskFile(const std::filesystem::path& png, const PixelRect& rect, bool has_measured, int first_row = 0);

}  // namespace mocap
