#pragma once
// The pieces of the PNG file format (PNG spec, 5.2-5.3) that the depth and label codecs share: the
// signature and the big-endian 32-bit fields of chunk headers.
#include <cstdint>

namespace mocap {

inline constexpr uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

/// The big-endian 32-bit value at `at` (chunk lengths, CRCs, IHDR's width and height).
inline uint32_t GetU32BigEndian(const uint8_t* at) {
  return (uint32_t{at[0]} << 24) | (uint32_t{at[1]} << 16) | (uint32_t{at[2]} << 8) | uint32_t{at[3]};
}

/// Stores `v` big-endian at `at`.
inline void PutU32BigEndian(uint8_t* at, uint32_t v) {
  at[0] = static_cast<uint8_t>(v >> 24), at[1] = static_cast<uint8_t>(v >> 16);
  at[2] = static_cast<uint8_t>(v >> 8), at[3] = static_cast<uint8_t>(v);
}

}  // namespace mocap
