// Against the real libfreenect (no LD_LIBRARY_PATH): on a machine without a Kinect1 opening must fail
// with a DeviceError that says so; with one attached, a few frames must arrive.
#include <gtest/gtest.h>

#include <atomic>

#include "capture/kinect/kinect1_device.h"

namespace mocap::capture {
namespace {

TEST(Kinect1Hardware, RealLibraryIsLoadedWithRegistration) {
  const LibfreenectInfo info = ProbeLibfreenect();
  EXPECT_TRUE(info.registration);
  EXPECT_FALSE(info.replay);
}

TEST(Kinect1Hardware, OpenFailsClearlyOrStreams) {
  auto device = CreateKinect1Device();
  try {
    device->Open();
  } catch (const DeviceError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("kinect1"), std::string::npos) << message;
    EXPECT_EQ(device->state(), DeviceState::kCreated);
    GTEST_SKIP() << "no Kinect1 here: " << message;
  }
  std::atomic<int> frames{0};
  device->Start([&](RgbdFrame&& frame) {
    EXPECT_EQ(frame.bgr.size(), cv::Size(640, 480));
    ++frames;
  });
  for (int i = 0; i < 50 && frames < 5; ++i) device->WaitForStreamEnd(100);
  device->Close();
  EXPECT_GE(frames.load(), 5);
}

TEST(Kinect1Options, CheckRejectsBadValues) {
  Kinect1Options options;
  options.pair_tolerance_ms = 0;
  EXPECT_THROW(CreateKinect1Device(options), InputError);
  options = {};
  options.device_index = -1;
  EXPECT_THROW(options.check(), InputError);
}

}  // namespace
}  // namespace mocap::capture
