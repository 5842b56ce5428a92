#include "capture/kinect/kinect2_support.h"

#include <gtest/gtest.h>

#include "core/check.h"

namespace mocap::capture {
namespace {

TEST(Kinect2Support, SaysWhetherItWasBuiltAndWhy) {
  const std::string detail = Kinect2SupportDetail();
  if (Kinect2SupportBuilt()) {
    EXPECT_NE(detail.find("libfreenect2"), std::string::npos) << detail;
    return;
  }
  EXPECT_NE(detail.find("not built"), std::string::npos) << detail;
  EXPECT_NE(detail.find("docs/kinect.md"), std::string::npos) << detail;
  try {
    CreateKinect2Device();
    FAIL() << "a Kinect2 device was created without libfreenect2";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("not built"), std::string::npos) << e.what();
  }
}

TEST(Kinect2Support, OptionsAreChecked) {
  Kinect2Options options;
  EXPECT_NO_THROW(options.check());
  options.max_depth_m = 0.4;  // below min_depth_m
  EXPECT_THROW(options.check(), InputError);
  options = {};
  options.pipeline = "vulkan";
  EXPECT_THROW(CreateKinect2Device(options), InputError);
  options = {};
  options.frame_timeout_ms = 0;
  EXPECT_THROW(options.check(), InputError);
}

}  // namespace
}  // namespace mocap::capture
