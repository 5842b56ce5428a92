#include "session/png_gray16.h"

#include <libdeflate.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <cstring>
#include <memory>

#include "core/check.h"
#include "session/png_format.h"

namespace mocap {
namespace {

constexpr size_t kBytesPerPixel = 2;                     // one 16-bit sample
constexpr uint64_t kMaxScanlineBytes = uint64_t{1} << 30;  // refuses absurd headers before allocating
// Deflate expands at most 1032:1 (zlib's FAQ): image data that cannot inflate to the size IHDR declares is
// refused before the scanline buffer is allocated, so a corrupt 100-byte file cannot cost a gigabyte.
constexpr uint64_t kMaxDeflateRatio = 1032;

libdeflate_decompressor& Decompressor() {
  struct Free {
    void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
  };
  thread_local std::unique_ptr<libdeflate_decompressor, Free> decompressor(libdeflate_alloc_decompressor());
  MOCAP_CHECK(decompressor != nullptr, "libdeflate_alloc_decompressor failed");
  return *decompressor;
}

struct Chunks {
  uint32_t width = 0, height = 0;
  bool gray16 = false;
  std::span<const uint8_t> first_idat;  // the first IDAT chunk's data, in the file's bytes
  std::vector<uint8_t> joined;          // all IDAT data joined, when there are several chunks
  std::span<const uint8_t> image_data() const { return joined.empty() ? first_idat : std::span<const uint8_t>(joined); }
};

/// Walks the chunks (PNG spec 5.3), checking every CRC; stops at IEND.
Chunks ReadChunks(std::span<const uint8_t> png, const std::string& where) {
  if (png.size() < sizeof(kPngSignature) || std::memcmp(png.data(), kPngSignature, sizeof(kPngSignature)) != 0)
    throw InputError(where, "not a PNG file (no PNG signature)");
  Chunks chunks;
  size_t idat_count = 0;
  for (size_t at = sizeof(kPngSignature);;) {
    if (png.size() - at < 12) throw InputError(where, Str("PNG is cut short at byte ", at, " (no IEND chunk)"));
    const uint32_t length = GetU32BigEndian(&png[at]);
    if (length > png.size() - at - 12)
      throw InputError(where, Str("PNG chunk at byte ", at, " claims ", length, " bytes, more than the file holds"));
    const uint8_t* type = &png[at + 4];
    const uint32_t crc = static_cast<uint32_t>(libdeflate_crc32(0, type, length + 4));
    if (crc != GetU32BigEndian(type + 4 + length))
      throw InputError(where, Str("PNG chunk '", std::string(reinterpret_cast<const char*>(type), 4), "' at byte ", at,
                                  " fails its CRC (corrupt file)"));
    const std::span<const uint8_t> data = png.subspan(at + 8, length);
    if (at == sizeof(kPngSignature)) {
      if (std::memcmp(type, "IHDR", 4) != 0 || length != 13) throw InputError(where, "PNG does not start with IHDR");
      chunks.width = GetU32BigEndian(&data[0]), chunks.height = GetU32BigEndian(&data[4]);
      // bit depth 16, colour type 0 (greyscale), compression 0, filter method 0, no interlace
      chunks.gray16 = data[8] == 16 && data[9] == 0 && data[10] == 0 && data[11] == 0 && data[12] == 0;
      if (!chunks.gray16) return chunks;
    } else if (std::memcmp(type, "IDAT", 4) == 0) {
      if (++idat_count == 1) chunks.first_idat = data;
      if (idat_count == 2) chunks.joined.assign(chunks.first_idat.begin(), chunks.first_idat.end());
      if (idat_count >= 2) chunks.joined.insert(chunks.joined.end(), data.begin(), data.end());
    } else if (std::memcmp(type, "IEND", 4) == 0) {
      break;
    }
    at += 12 + length;
  }
  if (idat_count == 0) throw InputError(where, "PNG has no image data (IDAT chunk)");
  return chunks;
}

uint8_t Paeth(int a, int b, int c) {  // PNG spec 9.4
  const int p = a + b - c;
  const int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return static_cast<uint8_t>(pa <= pb && pa <= pc ? a : (pb <= pc ? b : c));
}

/// SUB (PNG spec 9.2) for two-byte pixels: each byte plus the one two to its left, a running sum per
/// byte lane. With SSE2 eight pixels at a time: a log-step prefix sum within the vector plus the last
/// pixel of the one before (the scalar loop is a 2-byte dependency chain, 3-4x slower).
void UndoSub(uint8_t* row, size_t n) {
  size_t i = 0;
#if defined(__SSE2__)
  __m128i carry = _mm_setzero_si128();
  for (; i + 16 <= n; i += 16) {
    __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + i));
    x = _mm_add_epi8(x, _mm_slli_si128(x, 2));
    x = _mm_add_epi8(x, _mm_slli_si128(x, 4));
    x = _mm_add_epi8(x, _mm_slli_si128(x, 8));
    x = _mm_add_epi8(x, carry);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(row + i), x);
    carry = _mm_shuffle_epi32(_mm_shufflehi_epi16(x, _MM_SHUFFLE(3, 3, 3, 3)), _MM_SHUFFLE(3, 3, 3, 3));
  }
#endif
  for (i = std::max<size_t>(i, kBytesPerPixel); i < n; ++i) row[i] = static_cast<uint8_t>(row[i] + row[i - kBytesPerPixel]);
}

/// Undoes one row's filter in place (PNG spec 9.2); `prior` is the row above, already unfiltered (zeros
/// for the first row).
void Unfilter(uint8_t filter, uint8_t* __restrict row, const uint8_t* __restrict prior, size_t n,
              const std::string& where, size_t v) {
  constexpr size_t k = kBytesPerPixel;
  switch (filter) {
    case 0:
      return;
    case 1:
      return UndoSub(row, n);
    case 2:
      for (size_t i = 0; i < n; ++i) row[i] = static_cast<uint8_t>(row[i] + prior[i]);
      return;
    case 3:
      for (size_t i = 0; i < k; ++i) row[i] = static_cast<uint8_t>(row[i] + prior[i] / 2);
      for (size_t i = k; i < n; ++i) row[i] = static_cast<uint8_t>(row[i] + (row[i - k] + prior[i]) / 2);
      return;
    case 4:
      for (size_t i = 0; i < k; ++i) row[i] = static_cast<uint8_t>(row[i] + prior[i]);
      for (size_t i = k; i < n; ++i) row[i] = static_cast<uint8_t>(row[i] + Paeth(row[i - k], prior[i], prior[i - k]));
      return;
    default:
      throw InputError(where, Str("PNG row ", v, " has unknown filter type ", int{filter}, " (corrupt file)"));
  }
}

/// Big-endian samples times `scale`, rounded to float (written so that it vectorises).
void ScaleRow(const uint8_t* __restrict row, size_t width, double scale, float* __restrict out) {
  for (size_t u = 0; u < width; ++u) {
    uint16_t big_endian;
    std::memcpy(&big_endian, row + 2 * u, 2);
    out[u] = static_cast<float>(static_cast<double>(__builtin_bswap16(big_endian)) * scale);
  }
}

}  // namespace

std::optional<Image<float>> DecodeGray16Png(std::span<const uint8_t> png, double scale, const std::string& where) {
  const Chunks chunks = ReadChunks(png, where);
  if (!chunks.gray16) return std::nullopt;
  if (chunks.width == 0 || chunks.height == 0 || chunks.width > INT32_MAX || chunks.height > INT32_MAX)
    throw InputError(where, Str("PNG has an invalid size ", chunks.width, "x", chunks.height));
  const uint64_t row_bytes = kBytesPerPixel * uint64_t{chunks.width};
  const uint64_t total = (1 + row_bytes) * chunks.height;
  if (total > kMaxScanlineBytes)
    throw InputError(where, Str("PNG of ", chunks.width, "x", chunks.height, " is larger than this decoder takes"));
  const std::span<const uint8_t> data = chunks.image_data();
  if (total > kMaxDeflateRatio * data.size())
    throw InputError(where, Str("PNG image data is corrupt: ", data.size(), " bytes cannot inflate to the ", total,
                                " bytes of a ", chunks.width, "x", chunks.height, " image"));
  thread_local std::vector<uint8_t> scanlines;  // reused: no fresh pages to fault in per frame
  scanlines.resize(total);
  size_t inflated = 0;
  const libdeflate_result result =
      libdeflate_zlib_decompress(&Decompressor(), data.data(), data.size(), scanlines.data(), scanlines.size(), &inflated);
  if (result != LIBDEFLATE_SUCCESS || inflated != total)
    throw InputError(where, Str("PNG image data is corrupt: ",
                                result == LIBDEFLATE_INSUFFICIENT_SPACE ? "more data than its size"
                                : result == LIBDEFLATE_SUCCESS          ? Str("only ", inflated, " of ", total, " bytes")
                                                                        : std::string("zlib stream does not inflate")));
  Image<float> image(static_cast<int>(chunks.width), static_cast<int>(chunks.height));
  const std::vector<uint8_t> zeros(row_bytes, 0);
  const uint8_t* prior = zeros.data();
  for (size_t v = 0; v < chunks.height; ++v) {
    uint8_t* row = scanlines.data() + v * (1 + row_bytes);
    Unfilter(row[0], row + 1, prior, row_bytes, where, v);
    prior = row + 1;
    ScaleRow(prior, chunks.width, scale, image.data.data() + v * chunks.width);
  }
  return image;
}

}  // namespace mocap
