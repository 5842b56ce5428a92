#include "label/label_png.h"

#include <fcntl.h>
#include <unistd.h>
#include <libdeflate.h>
#include <zlib.h>

#include <bit>
#include <cerrno>
#include <cstring>
#include <opencv2/imgcodecs.hpp>

#include "core/check.h"
#include "label/deflate_rle.h"

namespace mocap {
namespace {

constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr uint8_t kFilterSub = 1;
static_assert(std::endian::native == std::endian::little, "Sub16 stores big-endian bytes through uint16_t");

/// One deflate stream per thread, reset per image (initialising one allocates and clears its ~270 kB
/// window and hash tables).
z_stream& Deflater(int level) {
  struct Stream {
    z_stream z{};
    int level = 0;
    ~Stream() {
      if (level != 0) deflateEnd(&z);
    }
  };
  thread_local Stream stream;
  if (stream.level != level) {
    if (stream.level != 0) deflateEnd(&stream.z);
    stream.z = z_stream{};
    MOCAP_CHECK(deflateInit2(&stream.z, level, Z_DEFLATED, 15, 8, Z_RLE) == Z_OK, "deflateInit2 failed");
    stream.level = level;
  }
  MOCAP_CHECK(deflateReset(&stream.z) == Z_OK, "deflateReset failed");
  return stream.z;
}

void PutU32(uint8_t* at, uint32_t v) {
  at[0] = static_cast<uint8_t>(v >> 24), at[1] = static_cast<uint8_t>(v >> 16);
  at[2] = static_cast<uint8_t>(v >> 8), at[3] = static_cast<uint8_t>(v);
}

/// Writes a chunk's length and type at `at`; its data follows them, its CRC is added by EndChunk.
uint8_t* BeginChunk(uint8_t* at, const char* type, size_t size) {
  PutU32(at, static_cast<uint32_t>(size));
  std::memcpy(at + 4, type, 4);
  return at + 8;
}

/// Appends the CRC (over type and data) of the chunk whose data starts at `data`; returns the end.
uint8_t* EndChunk(uint8_t* data, size_t size) {
  PutU32(data + size, static_cast<uint32_t>(libdeflate_crc32(0, data - 4, size + 4)));
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

/// The PNG scanlines of `image`, each a filter-type byte and the SUB-filtered row (big-endian samples).
void FilterRows(const cv::Mat& image, std::vector<uint8_t>& rows) {
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

/// zlib's deflate of `rows` at `level`, appended to `png`.
void AppendZlib(const std::vector<uint8_t>& rows, int level, std::vector<uint8_t>& png) {
  z_stream& z = Deflater(level);
  const size_t start = png.size(), bound = deflateBound(&z, static_cast<uLong>(rows.size()));
  png.resize(start + bound);
  z.next_in = const_cast<Bytef*>(rows.data());  // zlib's API is not const; it only reads the input
  z.avail_in = static_cast<uInt>(rows.size());
  z.next_out = png.data() + start;
  z.avail_out = static_cast<uInt>(bound);
  MOCAP_CHECK(deflate(&z, Z_FINISH) == Z_STREAM_END, "deflate: the output bound was too small");
  png.resize(start + z.total_out);
}

void Encode(const cv::Mat& image, const LabelPngOptions& options, std::vector<uint8_t>& png) {
  if (image.empty() || (image.type() != CV_8UC1 && image.type() != CV_16UC1))
    throw InputError("label PNG", Str("expected a non-empty 8- or 16-bit single-channel image, got OpenCV type ",
                                      image.type(), " of ", image.cols, "x", image.rows));
  thread_local std::vector<uint8_t> rows;  // reused: no fresh pages to fault in per image
  FilterRows(image, rows);
  png.resize(sizeof(kSignature) + 25 + 8);  // signature, IHDR chunk, IDAT length and type
  uint8_t* at = std::copy(std::begin(kSignature), std::end(kSignature), png.data());
  uint8_t* data = BeginChunk(at, "IHDR", 13);
  PutU32(data, static_cast<uint32_t>(image.cols));
  PutU32(data + 4, static_cast<uint32_t>(image.rows));
  const uint8_t ihdr_tail[5] = {static_cast<uint8_t>(image.depth() == CV_8U ? 8 : 16), 0, 0, 0, 0};  // grey, no interlace
  std::memcpy(data + 8, ihdr_tail, 5);
  EndChunk(data, 13);
  const size_t idat = sizeof(kSignature) + 25;
  if (options.zlib_level == 0) AppendZlibRle(rows.data(), rows.size(), png);
  else AppendZlib(rows, options.zlib_level, png);
  const size_t compressed = png.size() - idat - 8;
  png.resize(png.size() + 4 + 12);  // IDAT's CRC, the IEND chunk
  BeginChunk(png.data() + idat, "IDAT", compressed);
  at = EndChunk(png.data() + idat + 8, compressed);
  EndChunk(BeginChunk(at, "IEND", 0), 0);
}

}  // namespace

void LabelPngOptions::check() const {
  if (zlib_level < 0 || zlib_level > 9)
    throw InputError("label PNG options", Str("zlib_level ", zlib_level, " not in [0, 9]"));
}

std::vector<uint8_t> EncodeLabelPng(const cv::Mat& image, const LabelPngOptions& options) {
  options.check();
  std::vector<uint8_t> png;
  Encode(image, options, png);
  return png;
}

void WriteLabelPng(const std::filesystem::path& path, const cv::Mat& image, const LabelPngOptions& options) {
  options.check();
  if (image.type() == CV_8UC1 || image.type() == CV_16UC1) {
    thread_local std::vector<uint8_t> png;
    Encode(image, options, png);
    WriteFileBytes(path, png);
    return;
  }
  // OpenCV's speed path (SUB filter, zlib level 1) is taken only while no compression level is given;
  // an explicit level lets libpng try every row filter, at about twice the cost (bench/RESULTS.md).
  if (!cv::imwrite(path.string(), image, {cv::IMWRITE_PNG_STRATEGY, cv::IMWRITE_PNG_STRATEGY_RLE}))
    throw InputError(path.string(), "could not write the image (disk full or not writable?)");
}

void WriteFileBytes(const std::filesystem::path& path, const std::vector<uint8_t>& bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw InputError(path.string(), Str("cannot create the file: ", std::strerror(errno)));
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<size_t>(n);
  }
  const int error = done < bytes.size() ? errno : 0;
  if (::close(fd) != 0 || done < bytes.size()) {
    ::unlink(path.c_str());
    throw InputError(path.string(), Str("could not write the file (disk full or not writable?): ",
                                        std::strerror(error ? error : ENOSPC)));
  }
}

}  // namespace mocap
