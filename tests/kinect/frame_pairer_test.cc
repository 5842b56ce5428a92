#include "capture/kinect/frame_pairer.h"

#include <gtest/gtest.h>

namespace mocap::capture {
namespace {

StampedImage At(int64_t ticks) {
  StampedImage image;
  image.ticks = ticks;
  image.ticks_raw = static_cast<uint32_t>(ticks);
  image.image = cv::Mat(1, 1, CV_16UC1, cv::Scalar(static_cast<double>(ticks % 1000)));
  return image;
}

TEST(FramePairer, PairsWithinToleranceInEitherOrder) {
  FramePairer pairer(120'000);
  EXPECT_FALSE(pairer.AddDepth(At(1'000'000)));
  auto pair = pairer.AddColor(At(1'100'000));
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->depth.ticks, 1'000'000);
  EXPECT_EQ(pair->color.ticks, 1'100'000);
  EXPECT_FALSE(pairer.AddColor(At(3'000'000)));
  pair = pairer.AddDepth(At(2'880'000));  // exactly at the tolerance
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->color.ticks, 3'000'000);
  EXPECT_EQ(pairer.depth_unpaired(), 0);
  EXPECT_EQ(pairer.color_unpaired(), 0);
}

TEST(FramePairer, ImagesWithoutPartnerAreCountedNotDelivered) {
  FramePairer pairer(120'000);
  EXPECT_FALSE(pairer.AddDepth(At(0)));
  EXPECT_FALSE(pairer.AddDepth(At(2'000'000)));  // the first depth never got a colour image
  EXPECT_EQ(pairer.depth_unpaired(), 1);
  EXPECT_FALSE(pairer.AddColor(At(4'000'000)));  // too late for depth 2e6, which is dropped
  EXPECT_EQ(pairer.depth_unpaired(), 2);
  EXPECT_FALSE(pairer.AddDepth(At(1'000'000)));  // older than the waiting colour: never pairs
  EXPECT_EQ(pairer.depth_unpaired(), 3);
  auto pair = pairer.AddDepth(At(4'050'000));
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->color.ticks, 4'000'000);
  EXPECT_EQ(pairer.color_unpaired(), 0);
}

}  // namespace
}  // namespace mocap::capture
