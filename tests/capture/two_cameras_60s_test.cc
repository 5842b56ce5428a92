// Must-show of several cameras per daemon: a Kinect v1 and a Kinect v2 at its full sizes plus the
// tracker recorded for 60 s with zero drops, each camera's frames matching its source (JPEG bytes as
// they came, PNG pixels, depth values), all on one host clock (ctest label `slow`, about 95 s with the checks).
#include <gtest/gtest.h>

#include <filesystem>

#include "two_camera_rig.h"

namespace mocap::capture {
namespace {

// The frame queues hold 3 s per camera (90 frames; the Kinect1's are 1.5 MB each), so that other
// builds taking the 2 cores for a while delay the writer without dropping; drops stay counted.
TEST(TwoCameras, SixtySecondsWithoutDrops) {
  const testing::TwoCameraResult result = testing::RecordAndCheckTwoCameras("two_cameras_60s", 60.0, 90, 30);
  EXPECT_GT(result.summary["streams"]["kinect1"]["written"].get<int64_t>(), 1700) << result.summary.dump();
  EXPECT_GT(result.summary["streams"]["kinect2"]["written"].get<int64_t>(), 1700) << result.summary.dump();
  std::printf("%s\n", result.summary.dump().c_str());
  if (!HasFailure()) std::filesystem::remove_all(result.session_dir);  // 2 GB; kept when something failed
}

}  // namespace
}  // namespace mocap::capture
