// The depth PNG encoder (libdeflate) against OpenCV (libpng): every sample back exactly, for depth-like
// and real Kinect depth, odd sizes and every level; on real depth, files at least 5 % smaller than
// OpenCV's speed path writes; wrong input refused.
#include "session/png_write.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "core/check.h"
#include "depth_like.h"
#include "session/image_io.h"
#include "session/png_gray16.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using testing::DepthLike;

void ExpectSame(const cv::Mat& expected, const cv::Mat& actual) {
  ASSERT_EQ(actual.type(), CV_16UC1);
  ASSERT_EQ(actual.size(), expected.size());
  EXPECT_EQ(cv::countNonZero(expected != actual), 0);
}

TEST(DepthPngEncoder, LibpngReadsEverySampleBackAtEveryLevel) {
  for (const cv::Size size : {cv::Size(1, 1), cv::Size(7, 3), cv::Size(641, 5), cv::Size(64, 48)})
    for (const int level : {0, 1, kDefaultDepthPngLevel, 6, 12}) {
      SCOPED_TRACE(::testing::Message() << size << " level " << level);
      const cv::Mat units = DepthLike(size.width, size.height, static_cast<uint32_t>(size.area() + level));
      const std::vector<uint8_t> png = EncodeGray16Png(units, level);
      ExpectSame(units, cv::imdecode(png, cv::IMREAD_UNCHANGED));
      const auto ours = DecodeGray16Png(png, 1.0, "test");
      ASSERT_TRUE(ours.has_value());
      cv::Mat ours_units;
      cv::Mat(ours->height, ours->width, CV_32FC1, const_cast<float*>(ours->data.data())).convertTo(ours_units, CV_16UC1);
      ExpectSame(units, ours_units);
    }
}

TEST(DepthPngEncoder, NonContinuousInputIsEncodedByRows) {
  const cv::Mat big = DepthLike(100, 40, 5);
  const cv::Mat roi = big(cv::Rect(3, 2, 61, 30));
  ASSERT_FALSE(roi.isContinuous());
  ExpectSame(roi, cv::imdecode(EncodeGray16Png(roi), cv::IMREAD_UNCHANGED));
}

TEST(DepthPngEncoder, RealKinectDepthIsExactAndSmallerThanOpenCvsSpeedPath) {
  const fs::path dir = fs::path(MOCAP_SHARED_DIR) / "realdata/tum_fr1_desk_9frames/depth";
  if (!fs::exists(dir)) GTEST_SKIP() << dir << " not present";
  size_t ours_bytes = 0, opencv_bytes = 0;
  for (const auto& file : fs::directory_iterator(dir)) {
    const cv::Mat units = cv::imread(file.path().string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(units.type(), CV_16UC1) << file.path();
    const std::vector<uint8_t> png = EncodeDepthPng(units, 1.0 / 5000.0, -1);
    ExpectSame(units, cv::imdecode(png, cv::IMREAD_UNCHANGED));
    std::vector<uint8_t> opencv;
    ASSERT_TRUE(cv::imencode(".png", units, opencv));  // OpenCV's speed path: what the writer used before
    ours_bytes += png.size(), opencv_bytes += opencv.size();
  }
  ASSERT_GT(opencv_bytes, 0u);
  EXPECT_LT(static_cast<double>(ours_bytes), 0.95 * static_cast<double>(opencv_bytes));
}

TEST(DepthPngEncoder, RefusesOtherTypesAndLevels) {
  EXPECT_THROW(EncodeGray16Png(cv::Mat(4, 4, CV_8UC1, cv::Scalar(1))), InputError);
  EXPECT_THROW(EncodeGray16Png(cv::Mat(4, 4, CV_32FC1, cv::Scalar(1))), InputError);
  EXPECT_THROW(EncodeGray16Png(cv::Mat()), InputError);
  EXPECT_THROW(EncodeGray16Png(cv::Mat(4, 4, CV_16UC1, cv::Scalar(1)), 13), InputError);
  EXPECT_THROW(EncodeGray16Png(cv::Mat(4, 4, CV_16UC1, cv::Scalar(1)), -1), InputError);
}

}  // namespace
}  // namespace mocap
