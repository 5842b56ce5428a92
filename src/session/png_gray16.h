#pragma once
// A decoder for the one PNG kind every depth frame is stored as: 16-bit greyscale, not interlaced. It
// inflates with libdeflate (whole-buffer, 1.4-1.7x zlib's inflate on Kinect depth) and undoes the row
// filters itself, scaling in the same pass: a Kinect depth frame (640x480, 120 kB) takes 2.1 ms instead
// of OpenCV's 3.8-4.7 ms (bench/RESULTS.md, BM_MeasuredDepthPng). Every other PNG kind is left to
// OpenCV (the caller falls back on std::nullopt).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/image.h"

namespace mocap {

/// Decodes `png` (a whole file's bytes) when its header says 16-bit greyscale without interlacing, as
/// each sample times `scale` (computed in double, then rounded to float: 1.0 gives the samples
/// exactly, a depth unit gives metres); returns std::nullopt for any other PNG kind (colour, 8-bit,
/// palette, interlaced). Throws InputError
/// naming `where` for a file that is not a PNG or is corrupt: a chunk whose CRC does not match
/// (PNG spec 5.3), a zlib stream that does not inflate to exactly height * (1 + 2 * width) bytes or fails
/// its Adler-32, an unknown row filter type, or chunks cut short.
std::optional<Image<float>> DecodeGray16Png(std::span<const uint8_t> png, double scale, const std::string& where);

}  // namespace mocap
