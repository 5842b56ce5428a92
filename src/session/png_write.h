#pragma once
// PNG writing for single-channel 8- and 16-bit images (depth frames here, label images in label/): the
// SUB row filter, one IDAT chunk, no ancillary chunks. The files are standard PNGs; tests decode them
// with OpenCV (libpng) and compare every pixel.
//
// Depth frames are deflated with libdeflate instead of OpenCV's speed path (libpng, zlib level 1, RLE
// strategy, SUB filter): RLE leaves almost every byte of Kinect depth noise a literal, while libdeflate's
// matches cover its repeats. On the TUM Kinect frames, level 3 encodes in 5.6 ms instead of 7.1, into
// 11 % smaller files that read in 0.8-0.9 ms instead of 1.5 (bench/RESULTS.md, BM_DepthPngEncode and
// BM_DepthPngRead). Reading depth is the labeller's largest cost after rendering.
#include <cstddef>
#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <vector>

namespace mocap {

/// libdeflate level of the depth PNGs when the session writer is given no explicit level (-1).
inline constexpr int kDefaultDepthPngLevel = 3;

/// The PNG scanlines of `image` (CV_8UC1 or CV_16UC1, continuous or not): per row the SUB filter type
/// byte and the filtered row (PNG spec 9.2; 16-bit samples big-endian), into `rows` (resized).
void SubFilterScanlines(const cv::Mat& image, std::vector<uint8_t>& rows);

/// Starts the PNG file of `image` (CV_8UC1 or CV_16UC1, non-empty) in `png`, which is overwritten: the
/// signature, IHDR (greyscale, no interlace) and the IDAT chunk's header. The caller appends the zlib
/// stream of SubFilterScanlines' rows to `png`, then calls EndGrayPng with the returned offset (where
/// IDAT's data starts). Throws InputError for another type or an empty image.
size_t BeginGrayPng(const cv::Mat& image, std::vector<uint8_t>& png);

/// Finishes the file begun by BeginGrayPng: IDAT's length and CRC over what was appended, and IEND.
void EndGrayPng(size_t idat_data, std::vector<uint8_t>& png);

/// The PNG file bytes of `units` (CV_16UC1: depth in sensor units), deflated by libdeflate at `level`
/// (0 stores the rows uncompressed, 1..12; kDefaultDepthPngLevel is the writer's). Throws InputError for
/// another type, an empty image or a level outside 0..12.
std::vector<uint8_t> EncodeGray16Png(const cv::Mat& units, int level = kDefaultDepthPngLevel);

}  // namespace mocap
