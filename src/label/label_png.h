#pragma once
// PNG writing for label images (instance, class and packed mask PNGs): single-channel 8- or 16-bit
// images that are mostly constant. Encoded here rather than through OpenCV + libpng + zlib, which spend
// ~2 ms on a 640x480 16-bit label image: the SUB row filter and the chunks of session/png_write.h, then
// deflate with runs only (deflate_rle.h; what zlib's RLE strategy finds in label images, at a fraction of
// its cost), and the file written with a single write() call. The files are standard PNGs (any reader;
// tests decode them with OpenCV and compare every pixel).
#include <cstdint>
#include <filesystem>
#include <opencv2/core/mat.hpp>
#include <vector>

namespace mocap {

struct LabelPngOptions {
  /// 0: runs-only deflate (deflate_rle.h); 1..9: zlib's deflate at that level, for images that are not
  /// mostly runs (smaller files, several times the cost on label images).
  int zlib_level = 0;
  void check() const;     ///< throws InputError
};

/// The PNG file bytes of `image` (CV_8UC1 or CV_16UC1, continuous or not). Throws InputError for another
/// type or an empty image.
std::vector<uint8_t> EncodeLabelPng(const cv::Mat& image, const LabelPngOptions& options = {});

/// Writes `image` as a PNG: EncodeLabelPng for CV_8UC1 / CV_16UC1; OpenCV's speed path (SUB filter, zlib
/// level 1, RLE strategy) for other types (the colour overlay). Throws InputError when the file cannot be
/// written; no partial file is left behind then.
void WriteLabelPng(const std::filesystem::path& path, const cv::Mat& image, const LabelPngOptions& options = {});

/// Writes `bytes` as the file `path` with one write() call (the label files are written whole). Throws
/// InputError when that fails; no partial file is left behind then.
void WriteFileBytes(const std::filesystem::path& path, const std::vector<uint8_t>& bytes);

}  // namespace mocap
