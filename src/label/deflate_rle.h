#pragma once
// A zlib stream that encodes only byte runs (deflate matches at distance 1) and literals, with deflate's
// fixed Huffman codes: for label images, whose filtered rows are long runs of zeros, this is what zlib's
// Z_RLE strategy finds too, without zlib's copy of the input into its window and per-byte bookkeeping
// (~1.5 ms of a 640x480 16-bit label PNG). Any inflate decodes it (tests decode with zlib).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mocap {

/// Appends the zlib stream (header, one final fixed-Huffman block, Adler-32) of `data` to `out`.
void AppendZlibRle(const uint8_t* data, size_t size, std::vector<uint8_t>& out);

}  // namespace mocap
