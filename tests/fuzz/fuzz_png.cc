// The depth PNG decoder (session/png_gray16.h). The first byte selects how the rest becomes a PNG:
//   0: as it is;
//   1: re-framed: chunk lengths clamped to the bytes there and every CRC recomputed, so mutations reach
//      IHDR, IDAT and the zlib stream instead of stopping at the CRC test;
//   2: synthesised: a 16-bit greyscale PNG of 1..48 x 1..48 pixels whose scanlines (filter bytes
//      included) are the remaining bytes, deflated, in one or two IDAT chunks; this reaches the row
//      filters with every filter type and any pixel values.
// Bit 2 picks the scale (1 or a depth unit). Whenever the decoder returns an image, OpenCV (libpng) must
// decode the same file to the same samples.
#include <libdeflate.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "fuzz_common.h"
#include "session/png_format.h"
#include "session/png_gray16.h"

namespace {

using Bytes = std::vector<uint8_t>;

void AppendChunk(Bytes& png, const char* type, const uint8_t* data, size_t length) {
  uint8_t header[8];
  mocap::PutU32BigEndian(header, static_cast<uint32_t>(length));
  std::memcpy(header + 4, type, 4);
  png.insert(png.end(), header, header + 8);
  png.insert(png.end(), data, data + length);
  uint8_t crc[4];
  mocap::PutU32BigEndian(crc, static_cast<uint32_t>(libdeflate_crc32(libdeflate_crc32(0, type, 4), data, length)));
  png.insert(png.end(), crc, crc + 4);
}

Bytes Reframed(const uint8_t* data, size_t size) {
  Bytes png(mocap::kPngSignature, mocap::kPngSignature + 8);
  size_t at = std::min<size_t>(size, 8);
  while (size - at >= 12) {
    const size_t length = std::min<size_t>(mocap::GetU32BigEndian(data + at), size - at - 12);
    const char type[4] = {static_cast<char>(data[at + 4]), static_cast<char>(data[at + 5]), static_cast<char>(data[at + 6]),
                          static_cast<char>(data[at + 7])};
    AppendChunk(png, type, data + at + 8, length);
    at += 12 + length;
  }
  png.insert(png.end(), data + at, data + size);
  return png;
}

Bytes Synthesised(const uint8_t* data, size_t size) {
  if (size < 3) return {};
  const uint32_t width = 1 + data[0] % 48, height = 1 + data[1] % 48;
  const bool two_idat = data[2] & 1, exact_length = !(data[2] & 2);
  Bytes scanlines(data + 3, data + size);
  if (exact_length) scanlines.resize(size_t{height} * (1 + 2 * width));
  Bytes png(mocap::kPngSignature, mocap::kPngSignature + 8);
  uint8_t ihdr[13] = {};
  mocap::PutU32BigEndian(ihdr, width);
  mocap::PutU32BigEndian(ihdr + 4, height);
  ihdr[8] = 16;  // bit depth; colour type 0 (grey), no interlace
  AppendChunk(png, "IHDR", ihdr, sizeof(ihdr));
  libdeflate_compressor* compressor = libdeflate_alloc_compressor(1);
  Bytes z(libdeflate_zlib_compress_bound(compressor, scanlines.size()));
  z.resize(libdeflate_zlib_compress(compressor, scanlines.data(), scanlines.size(), z.data(), z.size()));
  libdeflate_free_compressor(compressor);
  const size_t first = two_idat ? z.size() / 2 : z.size();
  AppendChunk(png, "IDAT", z.data(), first);
  if (two_idat) AppendChunk(png, "IDAT", z.data() + first, z.size() - first);
  AppendChunk(png, "IEND", nullptr, 0);
  return png;
}

/// OpenCV must read what the decoder read, sample for sample.
void CompareWithOpenCv(const Bytes& png, const mocap::Image<float>& image, double scale) {
  const cv::Mat reference = cv::imdecode(cv::Mat(1, static_cast<int>(png.size()), CV_8U, const_cast<uint8_t*>(png.data())),
                                         cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
  if (reference.empty()) return;  // libpng is stricter about some files (it says so on stderr)
  if (reference.type() != CV_16UC1 || reference.cols != image.width || reference.rows != image.height) {
    std::fprintf(stderr, "fuzz_png: OpenCV reads %dx%d type %d, the decoder %dx%d\n", reference.cols, reference.rows,
                 reference.type(), image.width, image.height);
    std::abort();
  }
  for (int v = 0; v < image.height; ++v)
    for (int u = 0; u < image.width; ++u) {
      const float expected = static_cast<float>(reference.at<uint16_t>(v, u) * scale);
      if (image.data[static_cast<size_t>(v) * image.width + u] != expected) {
        std::fprintf(stderr, "fuzz_png: pixel (%d, %d) decodes to %g, OpenCV reads %g\n", u, v,
                     image.data[static_cast<size_t>(v) * image.width + u], expected);
        std::abort();
      }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const uint8_t mode = data[0] % 3;
  const double scale = (data[0] & 4) ? 1.0 / 5000 : 1.0;
  const Bytes png = mode == 0   ? Bytes(data + 1, data + size)
                    : mode == 1 ? Reframed(data + 1, size - 1)
                                : Synthesised(data + 1, size - 1);
  mocap::fuzz::ExpectValueOrInputError("fuzz_png", [&] {
    const auto image = mocap::DecodeGray16Png(png, scale, "fuzz.png");
    if (image) CompareWithOpenCv(png, *image, scale);
  });
  return 0;
}
