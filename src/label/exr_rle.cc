#include "label/exr_rle.h"

#include <bit>
#include <cstring>
#include <string>

#include "core/check.h"
#include "label/byte_runs.h"

namespace mocap {
namespace {

constexpr int kMinRun = 3, kMaxRun = 127;  // OpenEXR's ImfRle.cpp
constexpr uint8_t kRleCompression = 1;      // Imf::RLE_COMPRESSION
constexpr int32_t kFloatPixels = 2;         // Imf::FLOAT

// OpenEXR files are little-endian: values and float pixels are copied as they are in memory.
static_assert(std::endian::native == std::endian::little, "the EXR encoder assumes a little-endian machine");

template <typename T>
void Put(std::vector<uint8_t>& out, T value) {
  uint8_t bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.insert(out.end(), bytes, bytes + sizeof(T));
}

void PutString(std::vector<uint8_t>& out, const std::string& s) { out.insert(out.end(), s.c_str(), s.c_str() + s.size() + 1); }

void PutAttribute(std::vector<uint8_t>& out, const std::string& name, const std::string& type, int32_t size) {
  PutString(out, name);
  PutString(out, type);
  Put(out, size);
}

/// The magic number, version 2 (single-part scanline, short names) and the header attributes OpenEXR
/// requires, in the order its writer puts them.
void PutHeader(std::vector<uint8_t>& out, int width, int height) {
  Put<int32_t>(out, 20000630);
  Put<int32_t>(out, 2);
  PutAttribute(out, "channels", "chlist", 2 + 16 + 1);
  PutString(out, "Z");
  Put<int32_t>(out, kFloatPixels);
  Put<uint32_t>(out, 0);  // pLinear and three reserved bytes
  Put<int32_t>(out, 1), Put<int32_t>(out, 1);  // x and y sampling
  out.push_back(0);                            // end of the channel list
  PutAttribute(out, "compression", "compression", 1);
  out.push_back(kRleCompression);
  for (const char* window : {"dataWindow", "displayWindow"}) {
    PutAttribute(out, window, "box2i", 16);
    Put<int32_t>(out, 0), Put<int32_t>(out, 0), Put<int32_t>(out, width - 1), Put<int32_t>(out, height - 1);
  }
  PutAttribute(out, "lineOrder", "lineOrder", 1);
  out.push_back(0);  // increasing y
  PutAttribute(out, "pixelAspectRatio", "float", 4);
  Put<float>(out, 1.0f);
  PutAttribute(out, "screenWindowCenter", "v2f", 8);
  Put<float>(out, 0.0f), Put<float>(out, 0.0f);
  PutAttribute(out, "screenWindowWidth", "float", 4);
  Put<float>(out, 1.0f);
  out.push_back(0);  // end of the header
}

/// OpenEXR's RLE preprocessing of one scanline's little-endian bytes: even bytes then odd bytes, each
/// byte replaced by its difference to the one before it in that order plus 128 (mod 256). Written as
/// two forward passes over the input so that they vectorise.
void SplitAndPredict(const uint8_t* __restrict line, size_t size, std::vector<uint8_t>& split) {
  split.resize(size);  // size is even: whole floats
  const size_t half = size / 2;
  uint8_t* __restrict even = split.data();
  uint8_t* __restrict odd = split.data() + half;
  even[0] = line[0];
  for (size_t i = 1; i < half; ++i) even[i] = static_cast<uint8_t>(line[2 * i] - line[2 * i - 2] + 128);
  odd[0] = static_cast<uint8_t>(line[1] - line[2 * half - 2] + 128);  // follows the last even byte
  for (size_t i = 1; i < half; ++i) odd[i] = static_cast<uint8_t>(line[2 * i + 1] - line[2 * i - 1] + 128);
}

/// A scanline of zeros (no surface), as one chunk payload: the same for every such line of the image.
std::vector<uint8_t> ZeroLinePayload(size_t line_bytes) {
  const std::vector<uint8_t> zeros(line_bytes, 0);
  std::vector<uint8_t> split, packed;
  SplitAndPredict(zeros.data(), line_bytes, split);
  AppendExrRle(split.data(), split.size(), packed);
  return packed;
}

/// All bytes zero (bits, not values: -0.0 must keep its sign bit). `size` is a multiple of 4.
bool AllZeroBytes(const uint8_t* bytes, size_t size) {
  size_t i = 0;
  for (uint64_t word = 0; i + 8 <= size; i += 8) {
    std::memcpy(&word, bytes + i, 8);
    if (word != 0) return false;
  }
  for (; i < size; ++i)
    if (bytes[i] != 0) return false;
  return true;
}

}  // namespace

void AppendExrRle(const uint8_t* in, size_t size, std::vector<uint8_t>& out) {
  const size_t start = out.size();
  out.resize(start + size + size / kMaxRun + 2);  // worst case: all literals
  uint8_t* write = out.data() + start;
  const uint8_t* end = in + size;
  const uint8_t* run_start = in;
  const uint8_t* run_end = in + 1;
  while (run_start < end) {
    // OpenEXR's rleCompress: extend while equal and the run is at most kMaxRun + 1 bytes long
    const uint8_t* limit = end - run_start > kMaxRun + 1 ? run_start + kMaxRun + 1 : end;
    run_end += EqualBytes(run_end, limit, *run_start);
    if (run_end - run_start >= kMinRun) {  // a run: count - 1, then the byte
      *write++ = static_cast<uint8_t>(run_end - run_start - 1);
      *write++ = *run_start;
      run_start = run_end;
    } else {  // literals up to the next run of three equal bytes: -count, then the bytes
      while (run_end < end &&
             ((run_end + 1 >= end || *run_end != *(run_end + 1)) || (run_end + 2 >= end || *(run_end + 1) != *(run_end + 2))) &&
             run_end - run_start < kMaxRun)
        ++run_end;
      *write++ = static_cast<uint8_t>(-static_cast<int>(run_end - run_start));
      std::memcpy(write, run_start, static_cast<size_t>(run_end - run_start));
      write += run_end - run_start;
      run_start = run_end;
    }
    ++run_end;
  }
  out.resize(static_cast<size_t>(write - out.data()));
}

std::vector<uint8_t> EncodeDepthExrRle(const DepthImage& depth_m) {
  MOCAP_CHECK(depth_m.width > 0 && depth_m.height > 0, "empty depth image");
  std::vector<uint8_t> out;
  PutHeader(out, depth_m.width, depth_m.height);
  const size_t table_at = out.size();
  out.resize(table_at + 8 * static_cast<size_t>(depth_m.height));  // chunk offsets, filled below
  const size_t line_bytes = sizeof(float) * static_cast<size_t>(depth_m.width);
  out.reserve(out.size() + (line_bytes + 8) * static_cast<size_t>(depth_m.height));  // the worst case
  const std::vector<uint8_t> zero_line = ZeroLinePayload(line_bytes);
  std::vector<uint8_t> split, packed;
  for (int y = 0; y < depth_m.height; ++y) {
    const uint64_t offset = out.size();
    std::memcpy(out.data() + table_at + 8 * static_cast<size_t>(y), &offset, 8);
    const auto* line = reinterpret_cast<const uint8_t*>(depth_m.data.data() + static_cast<size_t>(y) * depth_m.width);
    if (AllZeroBytes(line, line_bytes)) {  // most lines of a label render: no surface
      packed = zero_line;
    } else {
      SplitAndPredict(line, line_bytes, split);
      packed.clear();
      AppendExrRle(split.data(), split.size(), packed);
    }
    const bool raw = packed.size() >= line_bytes;  // OpenEXR stores such lines uncompressed
    Put<int32_t>(out, y);
    Put<int32_t>(out, static_cast<int32_t>(raw ? line_bytes : packed.size()));
    if (raw) out.insert(out.end(), line, line + line_bytes);
    else out.insert(out.end(), packed.begin(), packed.end());
  }
  return out;
}

}  // namespace mocap
