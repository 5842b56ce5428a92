#include "capture/kinect/kinect1_depth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace mocap::capture {
namespace {

TEST(Kinect1Depth, FitValuesAtKnownCodes) {
  // z = 1 / (a raw + b): raw 0 is the nearest code, 2047 carries no depth.
  EXPECT_NEAR(Raw11ToDepthM(0), 1.0 / 3.3309495, 1e-12);
  EXPECT_NEAR(Raw11ToDepthM(800), 1.0 / (3.3309495 - 0.0030711 * 800), 1e-12);
  EXPECT_EQ(Raw11ToDepthM(kKinect1RawNoValue), 0.0);
  // Beyond the fit's pole (1/z <= 0 at raw >= 1085) and beyond 10 m: no value.
  EXPECT_EQ(Raw11ToDepthM(1085), 0.0);
  EXPECT_EQ(Raw11ToDepthM(1060), 0.0);
  EXPECT_GT(Raw11ToDepthM(1052), 9.0);
}

TEST(Kinect1Depth, DepthIncreasesWithCodeOverTheValidRange) {
  double previous = 0.0;
  for (uint16_t raw = 0; raw <= 1052; ++raw) {
    const double z = Raw11ToDepthM(raw);
    ASSERT_GT(z, previous) << "raw " << raw;
    previous = z;
  }
}

TEST(Kinect1Depth, RoundTripWithinHalfAStep) {
  for (double z = 0.35; z < 9.5; z += 0.0137) {
    const uint16_t raw = DepthMToRaw11(z);
    ASSERT_NE(raw, kKinect1RawNoValue) << z;
    const double error = std::abs(Raw11ToDepthM(raw) - z);
    EXPECT_LE(error, Raw11RoundTripErrorM(z) + 1e-12) << z;
    // The bound is about half a step (|a| z^2 / 2).
    EXPECT_LE(Raw11RoundTripErrorM(z), 0.6 * Raw11StepM(z)) << z;
  }
}

TEST(Kinect1Depth, StepSizesMatchTheReference) {
  // kinect.md §8: one disparity step is about 2.85e-3 z^2 (2.9 mm at 1 m); the fit gives 3.07e-3 z^2.
  EXPECT_NEAR(Raw11StepM(1.0), 3.0711e-3, 1e-9);
  EXPECT_NEAR(Raw11StepM(2.0), 4 * 3.0711e-3, 1e-9);
  // The actual distance between neighbouring codes at 1 m agrees with the derivative to 1 %.
  const uint16_t raw = DepthMToRaw11(1.0);
  EXPECT_NEAR(Raw11ToDepthM(raw + 1) - Raw11ToDepthM(raw), Raw11StepM(1.0), 0.01 * Raw11StepM(1.0));
}

TEST(Kinect1Depth, UnrepresentableDepthsAreNoValue) {
  EXPECT_EQ(DepthMToRaw11(0.0), kKinect1RawNoValue);
  EXPECT_EQ(DepthMToRaw11(-1.0), kKinect1RawNoValue);
  EXPECT_EQ(DepthMToRaw11(std::nan("")), kKinect1RawNoValue);
  EXPECT_EQ(DepthMToRaw11(0.25), kKinect1RawNoValue);  // nearer than raw 0 (0.300 m)
  EXPECT_EQ(DepthMToRaw11(12.0), kKinect1RawNoValue);  // beyond FREENECT_DEPTH_MM_MAX_VALUE
}

TEST(Kinect1Depth, TablesConvertBuffers) {
  const Raw11ToMmTable fit = Raw11ToMmTable::FromFit();
  EXPECT_FALSE(fit.from_device());
  EXPECT_EQ(fit[700], static_cast<uint16_t>(std::lround(Raw11ToDepthM(700) * 1000)));
  EXPECT_EQ(fit[kKinect1RawNoValue], 0);
  EXPECT_EQ(fit[5000], 0);  // out of the 11-bit range

  std::vector<uint16_t> device(2048);
  for (size_t i = 0; i < device.size(); ++i) device[i] = static_cast<uint16_t>(i * 7);
  const Raw11ToMmTable from_device = Raw11ToMmTable::FromDevice(device);
  EXPECT_TRUE(from_device.from_device());
  EXPECT_EQ(from_device[1000], 7000);
  EXPECT_EQ(from_device[1500], 0);  // 10500 mm is beyond the 10 m limit
  EXPECT_EQ(from_device[kKinect1RawNoValue], 0);

  const std::vector<uint16_t> raw = {0, 700, 2047, 1000};
  const cv::Mat mm = fit.Convert(raw.data(), 2, 2);
  ASSERT_EQ(mm.type(), CV_16UC1);
  EXPECT_EQ(mm.at<uint16_t>(0, 0), fit[0]);
  EXPECT_EQ(mm.at<uint16_t>(0, 1), fit[700]);
  EXPECT_EQ(mm.at<uint16_t>(1, 0), 0);
  EXPECT_EQ(mm.at<uint16_t>(1, 1), fit[1000]);
}

}  // namespace
}  // namespace mocap::capture
