// The fast 16-bit greyscale PNG decoder against OpenCV (libpng): identical samples for every row filter,
// odd widths, several IDAT chunks and real Kinect depth; other PNG kinds left to OpenCV; corrupt files
// refused with the reason.
#include "session/png_gray16.h"

#include <gtest/gtest.h>
#include <libdeflate.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "core/check.h"
#include "depth_like.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using testing::DepthLike;

uint32_t GetU32(const uint8_t* at) { return uint32_t{at[0]} << 24 | uint32_t{at[1]} << 16 | uint32_t{at[2]} << 8 | at[3]; }
void PutU32(uint8_t* at, uint32_t v) { at[0] = uint8_t(v >> 24), at[1] = uint8_t(v >> 16), at[2] = uint8_t(v >> 8), at[3] = uint8_t(v); }

std::vector<uint8_t> Encode(const cv::Mat& image, std::vector<int> params) {
  std::vector<uint8_t> png;
  EXPECT_TRUE(cv::imencode(".png", image, png, params));
  return png;
}

/// A PNG of `chunks` after the signature: each (type, data) with its length and CRC.
std::vector<uint8_t> Chunked(const std::vector<std::pair<std::string, std::vector<uint8_t>>>& chunks) {
  std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  for (const auto& [type, data] : chunks) {
    const size_t at = png.size();
    png.resize(at + 12 + data.size());
    PutU32(&png[at], static_cast<uint32_t>(data.size()));
    std::memcpy(&png[at + 4], type.data(), 4);
    std::copy(data.begin(), data.end(), png.begin() + static_cast<long>(at + 8));
    PutU32(&png[at + 8 + data.size()], static_cast<uint32_t>(libdeflate_crc32(0, &png[at + 4], data.size() + 4)));
  }
  return png;
}

/// A 16-bit greyscale PNG of `scanlines` (filter byte + filtered row, per row), deflated by libdeflate.
std::vector<uint8_t> PngOfScanlines(int width, int height, const std::vector<uint8_t>& scanlines) {
  std::vector<uint8_t> ihdr(13, 0);
  PutU32(&ihdr[0], static_cast<uint32_t>(width)), PutU32(&ihdr[4], static_cast<uint32_t>(height));
  ihdr[8] = 16;
  std::vector<uint8_t> z(libdeflate_zlib_compress_bound(nullptr, scanlines.size()));
  libdeflate_compressor* c = libdeflate_alloc_compressor(6);
  z.resize(libdeflate_zlib_compress(c, scanlines.data(), scanlines.size(), z.data(), z.size()));
  libdeflate_free_compressor(c);
  return Chunked({{"IHDR", ihdr}, {"IDAT", z}, {"IEND", {}}});
}

/// `image` with row v filtered by filter type v % 5 (PNG spec 9.2, two bytes per pixel).
std::vector<uint8_t> FilteredEveryWay(const cv::Mat& image) {
  const size_t n = 2 * static_cast<size_t>(image.cols);
  std::vector<uint8_t> plain(n * image.rows), out;
  for (int v = 0; v < image.rows; ++v)
    for (int u = 0; u < image.cols; ++u)
      plain[n * v + 2 * u] = uint8_t(image.at<uint16_t>(v, u) >> 8), plain[n * v + 2 * u + 1] = uint8_t(image.at<uint16_t>(v, u));
  for (int v = 0; v < image.rows; ++v) {
    const uint8_t* x = &plain[n * v];
    const std::vector<uint8_t> zeros(n, 0);
    const uint8_t* b = v > 0 ? &plain[n * (v - 1)] : zeros.data();
    out.push_back(static_cast<uint8_t>(v % 5));
    for (size_t i = 0; i < n; ++i) {
      const int left = i >= 2 ? x[i - 2] : 0, up = b[i], diag = i >= 2 ? b[i - 2] : 0;
      const int p = left + up - diag, pa = std::abs(p - left), pb = std::abs(p - up), pc = std::abs(p - diag);
      const int paeth = pa <= pb && pa <= pc ? left : (pb <= pc ? up : diag);
      const int predictor[5] = {0, left, up, (left + up) / 2, paeth};
      out.push_back(static_cast<uint8_t>(x[i] - predictor[v % 5]));
    }
  }
  return out;
}

void ExpectSame(const std::vector<uint8_t>& png, const cv::Mat& expected) {
  const std::optional<Image<float>> decoded = DecodeGray16Png(png, 1.0, "test.png");
  ASSERT_TRUE(decoded.has_value());
  ASSERT_EQ(decoded->width, expected.cols);
  ASSERT_EQ(decoded->height, expected.rows);
  cv::Mat expected_float;
  expected.convertTo(expected_float, CV_32FC1);
  const cv::Mat ours(decoded->height, decoded->width, CV_32FC1, const_cast<float*>(decoded->data.data()));
  EXPECT_EQ(cv::countNonZero(ours != expected_float), 0);
}

TEST(PngGray16, EveryRowFilterDecodesAsLibpng) {
  const cv::Mat image = DepthLike(97, 64, 1);
  const std::vector<uint8_t> png = PngOfScanlines(image.cols, image.rows, FilteredEveryWay(image));
  const cv::Mat libpng = cv::imdecode(png, cv::IMREAD_ANYDEPTH);
  ASSERT_EQ(cv::countNonZero(libpng != image), 0) << "the test's own filtering is wrong";
  ExpectSame(png, image);
  // libpng's adaptive filter choice (an explicit compression level) on the same content
  ExpectSame(Encode(image, {cv::IMWRITE_PNG_COMPRESSION, 9}), image);
}

TEST(PngGray16, SpeedSettingsOddWidthsAndOnePixel) {
  for (const cv::Size size : {cv::Size(640, 480), cv::Size(1, 1), cv::Size(1, 9), cv::Size(3, 2), cv::Size(511, 5)}) {
    const cv::Mat image = DepthLike(size.width, size.height, 7);
    ExpectSame(Encode(image, {}), image);  // OpenCV's speed path: SUB filter, zlib level 1, RLE
    ExpectSame(Encode(image, {cv::IMWRITE_PNG_COMPRESSION, 0}), image);  // stored blocks
  }
}

TEST(PngGray16, SeveralIdatChunksAreJoined) {
  const cv::Mat image = DepthLike(200, 150, 3);
  const std::vector<uint8_t> png = Encode(image, {cv::IMWRITE_PNG_COMPRESSION, 0});  // 60 kB, libpng splits at 8 kB
  int idats = 0;
  for (size_t at = 8; at + 12 <= png.size(); at += 12 + GetU32(&png[at])) idats += std::memcmp(&png[at + 4], "IDAT", 4) == 0;
  EXPECT_GT(idats, 1);
  ExpectSame(png, image);
}

TEST(PngGray16, RealKinectDepthDecodesAsLibpng) {
  const fs::path dir = fs::path(MOCAP_SHARED_DIR) / "realdata/tum_fr1_desk_9frames/depth";
  if (!fs::exists(dir)) GTEST_SKIP() << dir << " not present";
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    std::ifstream in(entry.path(), std::ios::binary);
    const std::vector<uint8_t> png((std::istreambuf_iterator<char>(in)), {});
    ExpectSame(png, cv::imdecode(png, cv::IMREAD_ANYDEPTH));
    ++files;
  }
  EXPECT_GT(files, 0);
}

TEST(PngGray16, OtherKindsAreLeftToOpenCv) {
  EXPECT_FALSE(DecodeGray16Png(Encode(cv::Mat(4, 4, CV_8UC1, cv::Scalar(9)), {}), 1.0, "g8.png").has_value());
  EXPECT_FALSE(DecodeGray16Png(Encode(cv::Mat(4, 4, CV_8UC3, cv::Scalar(1, 2, 3)), {}), 1.0, "bgr.png").has_value());
  EXPECT_FALSE(DecodeGray16Png(Encode(cv::Mat(4, 4, CV_16UC3, cv::Scalar(1, 2, 3)), {}), 1.0, "bgr16.png").has_value());
  std::vector<uint8_t> interlaced = Encode(cv::Mat(4, 4, CV_16UC1, cv::Scalar(5)), {});
  interlaced[8 + 8 + 12] = 1;  // IHDR's interlace method: Adam7
  PutU32(&interlaced[8 + 8 + 13], static_cast<uint32_t>(libdeflate_crc32(0, &interlaced[8 + 4], 17)));
  EXPECT_FALSE(DecodeGray16Png(interlaced, 1.0, "adam7.png").has_value());
}

std::string ErrorOf(const std::vector<uint8_t>& png) {
  try {
    DecodeGray16Png(png, 1.0, "bad.png");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(PngGray16, CorruptFilesAreRefusedWithTheReason) {
  const cv::Mat image = DepthLike(64, 48, 5);
  const std::vector<uint8_t> good = Encode(image, {});
  const size_t idat_data = 8 + 25 + 8;
  EXPECT_NE(ErrorOf({good.begin() + 1, good.end()}).find("not a PNG"), std::string::npos);
  EXPECT_NE(ErrorOf({good.begin(), good.begin() + static_cast<long>(good.size() / 2)}).find("more than the file holds"),
            std::string::npos);
  std::vector<uint8_t> flipped = good;
  flipped[idat_data + 10] ^= 0x40;
  EXPECT_NE(ErrorOf(flipped).find("fails its CRC"), std::string::npos);
  std::vector<uint8_t> no_iend(good.begin(), good.end() - 12);
  EXPECT_NE(ErrorOf(no_iend).find("cut short"), std::string::npos);
  EXPECT_NE(ErrorOf(no_iend).find("bad.png"), std::string::npos);
  // A valid stream for a smaller image under this header: inflates to too few bytes.
  std::vector<uint8_t> taller = good;
  PutU32(&taller[8 + 8 + 4], 49);
  PutU32(&taller[8 + 8 + 13], static_cast<uint32_t>(libdeflate_crc32(0, &taller[8 + 4], 17)));
  EXPECT_NE(ErrorOf(taller).find("only"), std::string::npos);
  std::vector<uint8_t> shorter = good;
  PutU32(&shorter[8 + 8 + 4], 47);
  PutU32(&shorter[8 + 8 + 13], static_cast<uint32_t>(libdeflate_crc32(0, &shorter[8 + 4], 17)));
  EXPECT_NE(ErrorOf(shorter).find("more data than its size"), std::string::npos);
}

// Found by tests/fuzz (fuzz_png): a 100-byte file declaring 16384 x 16384 pixels made the decoder allocate
// and zero 512 MiB before finding its data too short.
TEST(PngGray16, TinyDataForAHugeSizeIsRefusedBeforeAllocating) {
  std::vector<uint8_t> huge = PngOfScanlines(8, 2, std::vector<uint8_t>(2 * 17, 0));
  PutU32(&huge[8 + 8], 16384), PutU32(&huge[8 + 8 + 4], 16384);
  PutU32(&huge[8 + 8 + 13], static_cast<uint32_t>(libdeflate_crc32(0, &huge[8 + 4], 17)));
  const std::string error = ErrorOf(huge);
  EXPECT_NE(error.find("cannot inflate to the 536887296 bytes of a 16384x16384 image"), std::string::npos) << error;
}

TEST(PngGray16, UnknownFilterTypeIsRefused) {
  std::vector<uint8_t> scanlines(2 * 17, 0);
  scanlines[17] = 7;  // second row: filter type 7 does not exist
  EXPECT_NE(ErrorOf(PngOfScanlines(8, 2, scanlines)).find("row 1 has unknown filter type 7"), std::string::npos);
}

}  // namespace
}  // namespace mocap
