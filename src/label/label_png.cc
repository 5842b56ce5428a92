#include "label/label_png.h"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <opencv2/imgcodecs.hpp>

#include "core/check.h"
#include "label/deflate_rle.h"
#include "session/png_write.h"

namespace mocap {
namespace {

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
  thread_local std::vector<uint8_t> rows;  // reused: no fresh pages to fault in per image
  SubFilterScanlines(image, rows);
  const size_t idat = BeginGrayPng(image, png);
  if (options.zlib_level == 0) AppendZlibRle(rows.data(), rows.size(), png);
  else AppendZlib(rows, options.zlib_level, png);
  EndGrayPng(idat, png);
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
