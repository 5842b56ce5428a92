#pragma once
// Encoding and decoding of a session's images. Colour: PNG or JPEG (8-bit BGR). Depth: 16-bit PNG in
// the camera's depth_unit_m, or single-channel float OpenEXR ("Z", metres). Decoding checks that the file
// is whole (PNG IEND chunk, JPEG EOI marker), so a file cut short is an error, never a partly grey image.
#include <filesystem>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "core/image.h"

namespace mocap {

/// Encoded bytes of a colour image (CV_8UC3 BGR or CV_8UC1). `extension` is ".png" or ".jpg".
/// png_compression -1 selects OpenCV's speed-tuned PNG settings (level 1, SUB filter, RLE).
std::vector<uint8_t> EncodeColor(const cv::Mat& color, const std::string& extension, int png_compression,
                                 int jpeg_quality);
/// 16-bit PNG bytes of a depth image: CV_16UC1 is stored as is; CV_32FC1 metres are divided by
/// depth_unit_m and rounded (values beyond 65535 units, NaN and negatives become 0 = invalid). Deflated
/// by libdeflate (png_write.h) at png_compression, or at kDefaultDepthPngLevel for -1.
std::vector<uint8_t> EncodeDepthPng(const cv::Mat& depth, double depth_unit_m, int png_compression);
/// Writes a float OpenEXR depth file (channel "Z", metres; CV_16UC1 input is scaled by depth_unit_m).
void WriteDepthExr(const std::filesystem::path& path, const cv::Mat& depth, double depth_unit_m);

/// True when `bytes` look like a whole JPEG: the start-of-image marker (FF D8 FF) first and the
/// end-of-image marker (FF D9) last. What a writer checks before storing encoded colour as it is.
bool IsWholeJpeg(const std::vector<uint8_t>& bytes);

/// Colour as CV_8UC3 BGR. Throws InputError naming the file when absent, truncated or not an image.
cv::Mat ReadColor(const std::filesystem::path& path);
/// Depth in metres (0 = invalid): a 16-bit PNG scaled by depth_unit_m, or an OpenEXR "Z" channel.
/// Throws InputError naming the file when absent, truncated, of the wrong type, or not an image.
DepthImage ReadDepth(const std::filesystem::path& path, double depth_unit_m);
/// An id image (a label run's instance or class PNG, a user's mask: single-channel 8- or 16-bit PNG, 0 =
/// background). Throws InputError naming the file when absent, truncated, colour or not an image.
LabelImage ReadIdImage(const std::filesystem::path& path);

}  // namespace mocap
