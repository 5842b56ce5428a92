#pragma once
// The scan both run-length encoders of the label files spend their time in (deflate_rle.cc for the
// label PNGs, exr_rle.cc for the rendered depth): how long a run of one byte value goes on.
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace mocap {

/// How many bytes from `at` on (before `end`) equal `byte`, eight at a time where they can.
/// Precondition: at <= end.
inline size_t EqualBytes(const uint8_t* at, const uint8_t* end, uint8_t byte) {
  const uint64_t pattern = 0x0101010101010101ull * byte;
  const auto limit = static_cast<size_t>(end - at);
  size_t n = 0;
  for (uint64_t word = 0; n + 8 <= limit; n += 8) {
    std::memcpy(&word, at + n, 8);
    if (word != pattern) break;
  }
  while (n < limit && at[n] == byte) ++n;
  return n;
}

}  // namespace mocap
