#pragma once
// Rendered depth as a single-channel 32-bit float OpenEXR file ("Z", metres), with a choice of
// lossless compression. Half floats are not offered: their 11-bit significand spaces values 0.5 mm
// apart at 0.5-1 m and 2 mm at 2-4 m, as coarse as the depth errors the labels are checked against.
#include <filesystem>
#include <string>

#include "core/image.h"

namespace mocap {

/// OpenEXR's lossless codecs (bench/RESULTS.md, bench_label, has their cost on rendered depth).
enum class DepthCompression { kNone, kRle, kZips, kZip, kPiz };

/// "none", "rle", "zips", "zip", "piz"; throws InputError for another name.
DepthCompression DepthCompressionFromString(const std::string& name);
const char* DepthCompressionName(DepthCompression compression);

/// Writes `depth_m` (0 = no surface). Throws InputError when the file cannot be written; no file is left
/// behind then.
void WriteRenderedDepthExr(const std::filesystem::path& path, const DepthImage& depth_m, DepthCompression compression);

}  // namespace mocap
