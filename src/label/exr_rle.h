#pragma once
// The rendered depth as an OpenEXR file with RLE compression, encoded here: OpenEXR's own writer spends
// ~4 ms on a 640x480 float image whether it compresses or not (its per-scanline machinery and stream
// writes), most of the depth output's cost (bench/RESULTS.md, bench_label). The file is what OpenEXR
// writes for the same image and codec: a single-part scanline file, one float channel "Z", one scanline
// per chunk, each chunk OpenEXR's RLE of the byte-split, delta-predicted line (stored raw where that is
// not smaller). Readers decode it with the stock library (tests compare every value).
#include <cstdint>
#include <vector>

#include "core/image.h"

namespace mocap {

/// The OpenEXR file bytes of `depth_m` (channel "Z", 32-bit float, RLE). Precondition: not empty.
std::vector<uint8_t> EncodeDepthExrRle(const DepthImage& depth_m);

/// OpenEXR's RLE of `in` (its rleCompress: runs of 3..128 equal bytes as count-1 and the byte, other
/// bytes as a negative count and up to 127 literals), appended to `out`.
void AppendExrRle(const uint8_t* in, size_t size, std::vector<uint8_t>& out);

}  // namespace mocap
