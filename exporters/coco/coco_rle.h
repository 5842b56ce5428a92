#pragma once
// COCO run-length encoding of binary masks, bit-compatible with cocoapi's common/maskApi.c (the C core of
// pycocotools.mask), so that `pycocotools.mask.decode`, `area` and `toBbox` give back exactly our masks,
// areas and boxes (docs/export.md "COCO").
//
//  - Uncompressed RLE (maskApi.c rleEncode): the image is read column by column (Fortran order: pixel
//    (u, v) is at position u * height + v) and cut into runs of equal value; `counts` holds the run
//    lengths, starting with a run of 0s (length 0 when the first pixel is set), so odd entries are 1s.
//  - Compressed string (maskApi.c rleToString): each count, from the fourth on, as the difference to the
//    count two before; each value as 5-bit groups, least significant first, ASCII 48 + group, bit 0x20
//    set while more groups follow, the last group's bit 0x10 the sign (a LEB128 variant).
//  - toBbox (maskApi.c rleToBbox): [x, y, w, h] of the set pixels with w = x_max - x_min + 1 (a single
//    pixel is [x, y, 1, 1]); [0, 0, 0, 0] for an empty mask.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "render/canvas.h"

namespace mocap::exporters {

/// An uncompressed COCO RLE of a height x width mask.
struct CocoRle {
  int height = 0, width = 0;
  std::vector<uint32_t> counts;  ///< column-major run lengths, first a run of 0s; they sum to height * width
};

/// RLE of a full-image mask (CV_8UC1, any non-zero byte is set; a view with row padding is fine).
CocoRle EncodeCocoRle(const cv::Mat& mask);

/// RLE of an image_width x image_height mask that is zero outside `rect`, from the rect-sized crop
/// (row-major, 1 byte per pixel, non-zero = set) without building the full image. Parts of `rect` outside
/// the image are ignored. Precondition: crop.size() == rect.width * rect.height (or rect empty).
CocoRle EncodeCocoRle(const std::vector<uint8_t>& crop, const PixelRect& rect, int image_width, int image_height);

/// The compressed `counts` string, byte for byte as maskApi.c rleToString writes it.
std::string CocoRleString(const std::vector<uint32_t>& counts);

/// Inverse of CocoRleString (maskApi.c rleFrString), for diagnostics. Throws InputError naming `where`
/// for a character outside '0'..'o', a string that ends inside a value or a count that is negative or
/// does not fit 32 bits.
std::vector<uint32_t> CocoRleCountsFromString(std::string_view text, const std::string& where);

/// Set pixels (pycocotools.mask.area).
int64_t CocoRleArea(const CocoRle& rle);

/// COCO box [x, y, w, h] of the set pixels (pycocotools.mask.toBbox); [0, 0, 0, 0] when none.
std::array<double, 4> CocoRleBox(const CocoRle& rle);

}  // namespace mocap::exporters
