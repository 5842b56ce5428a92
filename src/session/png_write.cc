#include "session/png_write.h"

#include <libdeflate.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <memory>

#include "core/check.h"
#include "session/png_format.h"

namespace mocap {
namespace {

constexpr uint8_t kFilterSub = 1;
constexpr size_t kIhdrEnd = sizeof(kPngSignature) + 25;  // signature, IHDR (length, type, 13 bytes, CRC)
static_assert(std::endian::native == std::endian::little, "Sub16 stores big-endian bytes through uint16_t");

/// Writes a chunk's length and type at `at`; its data follows them, its CRC is added by EndChunk.
uint8_t* BeginChunk(uint8_t* at, const char* type, size_t size) {
  PutU32BigEndian(at, static_cast<uint32_t>(size));
  std::memcpy(at + 4, type, 4);
  return at + 8;
}

/// Appends the CRC (over type and data) of the chunk whose data starts at `data`; returns the end.
uint8_t* EndChunk(uint8_t* data, size_t size) {
  PutU32BigEndian(data + size, static_cast<uint32_t>(libdeflate_crc32(0, data - 4, size + 4)));
  return data + size + 4;
}

/// SUB-filtered big-endian bytes of one 16-bit row (PNG spec 9.2: each byte minus the one two before),
/// computed on whole 16-bit lanes so that it vectorises: per pixel, high bytes and low bytes are
/// subtracted separately (no borrow between them) and stored high byte first.
void Sub16(const uint16_t* __restrict in, int width, uint16_t* __restrict out) {
  out[0] = static_cast<uint16_t>(in[0] << 8 | in[0] >> 8);
  for (int u = 1; u < width; ++u) {
    const auto high = static_cast<uint16_t>(((in[u] >> 8) - (in[u - 1] >> 8)) & 0xff);
    const auto low = static_cast<uint16_t>((in[u] - in[u - 1]) & 0xff);
    out[u] = static_cast<uint16_t>(low << 8 | high);  // in memory (little-endian): high byte, then low
  }
}

void CheckGray(const cv::Mat& image, const char* what) {
  if (image.empty() || (image.type() != CV_8UC1 && image.type() != CV_16UC1))
    throw InputError(what, Str("expected a non-empty 8- or 16-bit single-channel image, got OpenCV type ",
                               image.type(), " of ", image.cols, "x", image.rows));
}

libdeflate_compressor& Compressor(int level) {
  struct Free {
    void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
  };
  // One per thread and level: allocating one sets up its hash tables (hundreds of kB).
  thread_local std::unique_ptr<libdeflate_compressor, Free> compressors[13];
  auto& compressor = compressors[level];
  if (!compressor) compressor.reset(libdeflate_alloc_compressor(level));
  MOCAP_CHECK(compressor != nullptr, "libdeflate_alloc_compressor(", level, ") failed");
  return *compressor;
}

}  // namespace

void SubFilterScanlines(const cv::Mat& image, std::vector<uint8_t>& rows) {
  CheckGray(image, "PNG");
  // Bounds in locals: stores through uint8_t* may alias anything, which would make the compiler reload
  // image.cols in every iteration and keep the loops from vectorising.
  const int width = image.cols, height = image.rows;
  const bool eight_bit = image.depth() == CV_8U;
  const size_t row_bytes = 1 + image.elemSize() * static_cast<size_t>(width);
  rows.resize(row_bytes * static_cast<size_t>(height));
  thread_local std::vector<uint16_t> filtered;
  filtered.resize(static_cast<size_t>(width));
  for (int v = 0; v < height; ++v) {
    uint8_t* __restrict out = rows.data() + row_bytes * static_cast<size_t>(v);
    *out++ = kFilterSub;
    if (eight_bit) {
      const uint8_t* __restrict in = image.ptr<uint8_t>(v);
      out[0] = in[0];
      for (int u = 1; u < width; ++u) out[u] = static_cast<uint8_t>(in[u] - in[u - 1]);
    } else {
      Sub16(image.ptr<uint16_t>(v), width, filtered.data());
      std::memcpy(out, filtered.data(), 2 * static_cast<size_t>(width));  // the row is at an odd offset
    }
  }
}

size_t BeginGrayPng(const cv::Mat& image, std::vector<uint8_t>& png) {
  CheckGray(image, "PNG");
  png.resize(kIhdrEnd + 8);  // + IDAT's length and type
  uint8_t* at = std::copy(std::begin(kPngSignature), std::end(kPngSignature), png.data());
  uint8_t* data = BeginChunk(at, "IHDR", 13);
  PutU32BigEndian(data, static_cast<uint32_t>(image.cols));
  PutU32BigEndian(data + 4, static_cast<uint32_t>(image.rows));
  // bit depth, colour type 0 (greyscale), compression 0, filter method 0, no interlace
  const uint8_t tail[5] = {static_cast<uint8_t>(image.depth() == CV_8U ? 8 : 16), 0, 0, 0, 0};
  std::memcpy(data + 8, tail, 5);
  EndChunk(data, 13);
  return kIhdrEnd + 8;
}

void EndGrayPng(size_t idat_data, std::vector<uint8_t>& png) {
  MOCAP_CHECK(idat_data == kIhdrEnd + 8 && png.size() >= idat_data, "EndGrayPng: not a file begun by BeginGrayPng");
  const size_t compressed = png.size() - idat_data;
  png.resize(png.size() + 4 + 12);  // IDAT's CRC, the IEND chunk
  BeginChunk(png.data() + kIhdrEnd, "IDAT", compressed);
  uint8_t* at = EndChunk(png.data() + idat_data, compressed);
  EndChunk(BeginChunk(at, "IEND", 0), 0);
}

std::vector<uint8_t> EncodeGray16Png(const cv::Mat& units, int level) {
  if (units.empty() || units.type() != CV_16UC1)
    throw InputError("depth PNG", Str("expected a non-empty CV_16UC1 image, got OpenCV type ", units.type(), " of ",
                                      units.cols, "x", units.rows));
  if (level < 0 || level > 12) throw InputError("depth PNG", Str("libdeflate level ", level, " not in [0, 12]"));
  thread_local std::vector<uint8_t> rows;  // reused: no fresh pages to fault in per frame
  SubFilterScanlines(units, rows);
  std::vector<uint8_t> png;
  const size_t idat = BeginGrayPng(units, png);
  libdeflate_compressor& compressor = Compressor(level);
  png.resize(idat + libdeflate_zlib_compress_bound(&compressor, rows.size()));
  const size_t size =
      libdeflate_zlib_compress(&compressor, rows.data(), rows.size(), png.data() + idat, png.size() - idat);
  MOCAP_CHECK(size > 0, "libdeflate_zlib_compress: the output bound was too small");
  png.resize(idat + size);
  EndGrayPng(idat, png);
  return png;
}

}  // namespace mocap
