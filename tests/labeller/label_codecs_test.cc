// The label PNG and RLE OpenEXR encoders (label_png.h, exr_rle.h) write standard files: OpenCV's PNG
// decoder and OpenEXR's reader must give back every pixel exactly, and the RLE must match OpenEXR's
// format on edge cases (run lengths at the limits, incompressible lines stored raw).
#include <gtest/gtest.h>

#include <ImfRgbaFile.h>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <zlib.h>

#include "core/check.h"
#include "label/depth_exr.h"
#include "label/deflate_rle.h"
#include "label/exr_rle.h"
#include "label/label_png.h"
#include "labeller_test_util.h"
#include "session/image_io.h"

namespace mocap {
namespace {

/// OpenEXR's rleUncompress (ImfRle.cpp), as the reference the encoder must satisfy.
std::vector<uint8_t> RleDecode(const std::vector<uint8_t>& in) {
  std::vector<uint8_t> out;
  for (size_t i = 0; i < in.size();) {
    const auto count = static_cast<int8_t>(in[i++]);
    if (count < 0) {
      out.insert(out.end(), in.begin() + static_cast<ptrdiff_t>(i), in.begin() + static_cast<ptrdiff_t>(i) - count);
      i += static_cast<size_t>(-count);
    } else {
      out.insert(out.end(), static_cast<size_t>(count) + 1, in[i++]);
    }
  }
  return out;
}

TEST(ExrRle, RoundTripsRunsAndLiterals) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<uint8_t> data;
    const int pieces = static_cast<int>(rng() % 12);
    for (int p = 0; p < pieces; ++p) {
      const size_t length = rng() % 300;  // runs and literal stretches beyond the 127/128 limits
      const bool run = rng() % 2 == 0;
      const auto byte = static_cast<uint8_t>(rng());
      for (size_t k = 0; k < length; ++k) data.push_back(run ? byte : static_cast<uint8_t>(rng() % 3));
    }
    std::vector<uint8_t> packed;
    AppendExrRle(data.data(), data.size(), packed);
    EXPECT_EQ(RleDecode(packed), data) << "trial " << trial;
  }
  std::vector<uint8_t> zeros(1280, 0), packed;
  AppendExrRle(zeros.data(), zeros.size(), packed);
  EXPECT_EQ(packed.size(), 2u * 10);  // ten runs of 128 bytes
}

TEST(DeflateRle, ZlibInflatesItExactly) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<uint8_t> data;
    const int pieces = static_cast<int>(rng() % 10);
    for (int p = 0; p < pieces; ++p) {  // runs around and beyond deflate's 258-byte match limit
      const size_t length = rng() % 700;
      const auto byte = static_cast<uint8_t>(rng());
      for (size_t k = 0; k < length; ++k) data.push_back(rng() % 3 == 0 ? static_cast<uint8_t>(rng()) : byte);
      data.insert(data.end(), rng() % 600, byte);
    }
    std::vector<uint8_t> packed;
    AppendZlibRle(data.data(), data.size(), packed);
    std::vector<uint8_t> back(data.size() + 1);
    uLongf back_size = back.size();
    ASSERT_EQ(uncompress(back.data(), &back_size, packed.data(), packed.size()), Z_OK) << "trial " << trial;
    back.resize(back_size);
    EXPECT_EQ(back, data) << "trial " << trial;  // uncompress also checks the Adler-32
  }
}

DepthImage TestDepth(int width, int height) {
  DepthImage depth(width, height, 0.0f);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> z(0.3f, 4.0f);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      if (v < 3) depth.at(u, v) = z(rng);                         // incompressible lines: stored raw
      else if (v < 10) depth.at(u, v) = 1.5f;                     // constant
      else if ((u - 40) * (u - 40) + (v - 30) * (v - 30) < 300) depth.at(u, v) = 0.7f + 1e-4f * float(u * v);
    }
  }
  return depth;
}

TEST(ExrRle, OpenExrReadsTheFileExactly) {
  const auto dir = testing::FreshDir("exr_rle");
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{97, 61}, {1, 1}, {640, 12}}) {
    const DepthImage depth = TestDepth(w, h);
    WriteRenderedDepthExr(dir / "d.exr", depth, DepthCompression::kRle);
    const DepthImage back = ReadDepth(dir / "d.exr", 1.0);
    ASSERT_EQ(back.width, w);
    ASSERT_EQ(back.height, h);
    EXPECT_EQ(back.data, depth.data) << w << "x" << h;
    Imf::RgbaInputFile file((dir / "d.exr").c_str());  // the header as OpenEXR sees it
    EXPECT_EQ(file.compression(), Imf::RLE_COMPRESSION);
    EXPECT_EQ(file.displayWindow().max.x, w - 1);
  }
  // No smaller than OpenEXR's own RLE of the same image (same algorithm).
  const DepthImage depth = TestDepth(640, 48);
  const size_t ours = EncodeDepthExrRle(depth).size();
  WriteRenderedDepthExr(dir / "none.exr", depth, DepthCompression::kNone);
  EXPECT_LT(ours, std::filesystem::file_size(dir / "none.exr") / 2);
  std::filesystem::remove_all(dir);
}

TEST(LabelPng, OpenCvDecodesEveryPixel) {
  const auto dir = testing::FreshDir("label_png");
  std::mt19937 rng(7);
  cv::Mat ids16(48, 70, CV_16UC1, cv::Scalar(0)), mask8(33, 17, CV_8UC1, cv::Scalar(0));
  cv::rectangle(ids16, {10, 5, 30, 20}, 3, -1);
  cv::circle(ids16, {40, 30}, 12, 65535, -1);
  for (int i = 0; i < 200; ++i) ids16.at<uint16_t>(static_cast<int>(rng() % 48), static_cast<int>(rng() % 70)) = static_cast<uint16_t>(rng());
  for (int i = 0; i < 100; ++i) mask8.at<uint8_t>(static_cast<int>(rng() % 33), static_cast<int>(rng() % 17)) = static_cast<uint8_t>(rng() % 8);
  const cv::Mat roi = ids16(cv::Rect(3, 4, 50, 40));  // not continuous: rows have a stride
  for (const cv::Mat& image : {ids16, mask8, roi}) {
    for (int level : {0, 1, 6}) {
      const std::vector<uint8_t> png = EncodeLabelPng(image, {.zlib_level = level});
      const cv::Mat back = cv::imdecode(png, cv::IMREAD_UNCHANGED);
      ASSERT_EQ(back.type(), image.type()) << level;
      EXPECT_EQ(cv::countNonZero(back != image), 0) << level;
    }
    WriteLabelPng(dir / "x.png", image);
    const cv::Mat back = cv::imread((dir / "x.png").string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(back.type(), image.type());
    ASSERT_EQ(back.size(), image.size());
    EXPECT_EQ(cv::countNonZero(back != image), 0);
  }
  EXPECT_THROW(EncodeLabelPng(cv::Mat(4, 4, CV_32FC1)), InputError);
  EXPECT_THROW(WriteLabelPng(dir / "no" / "such" / "x.png", mask8), InputError);
  EXPECT_THROW(EncodeLabelPng(mask8, {.zlib_level = 10}), InputError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mocap
