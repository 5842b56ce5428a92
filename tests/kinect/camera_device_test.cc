// The CameraDevice bookkeeping (states, sequence numbers, stream end) with a minimal scripted subclass.
#include "capture/kinect/camera_device.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace mocap::capture {
namespace {

class ScriptedDevice final : public CameraDevice {
 public:
  explicit ScriptedDevice(int frames, bool fail_open = false)
      : CameraDevice("scripted"), frames_(frames), fail_open_(fail_open) {}
  ~ScriptedDevice() override { Close(); }
  std::vector<std::string> calls;

 private:
  void DoOpen() override {
    calls.push_back("open");
    if (fail_open_) throw DeviceError("scripted: not attached");
  }
  void DoStart() override {
    calls.push_back("start");
    thread_ = std::thread([this] {
      for (int i = 0; i < frames_; ++i) {
        RgbdFrame frame;
        frame.depth_ticks = 2'000'000 * i;
        frame.ticks_per_second = 60e6;
        Deliver(std::move(frame));
      }
      ReportStreamEnd("script done");
    });
  }
  void DoStop() override {
    calls.push_back("stop");
    thread_.join();
  }
  void DoClose() override { calls.push_back("close"); }

  int frames_;
  bool fail_open_;
  std::thread thread_;
};

TEST(CameraDevice, WalksTheStatesAndNumbersFrames) {
  ScriptedDevice device(5);
  EXPECT_EQ(device.state(), DeviceState::kCreated);
  device.Open();
  EXPECT_EQ(device.state(), DeviceState::kOpen);
  std::vector<RgbdFrame> got;
  device.Start([&](RgbdFrame&& frame) { got.push_back(std::move(frame)); });
  EXPECT_EQ(device.state(), DeviceState::kStreaming);
  ASSERT_TRUE(device.WaitForStreamEnd(5000));
  EXPECT_EQ(device.stream_end_reason().value_or(""), "script done");
  device.Close();  // stops first
  EXPECT_EQ(device.state(), DeviceState::kClosed);
  EXPECT_EQ(device.calls, (std::vector<std::string>{"open", "start", "stop", "close"}));
  ASSERT_EQ(got.size(), 5u);
  for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i].sequence, static_cast<int64_t>(i));
  EXPECT_EQ(device.stats().frames_delivered, 5);
  // 4 frames * 2e6 ticks at 60 MHz = 133.333 ms.
  EXPECT_EQ(got[4].depth_device_ns(), 133'333'333);
}

TEST(CameraDevice, FailedOpenStaysCreated) {
  ScriptedDevice device(0, /*fail_open=*/true);
  EXPECT_THROW(device.Open(), DeviceError);
  EXPECT_EQ(device.state(), DeviceState::kCreated);
  device.Close();
  EXPECT_EQ(device.calls, (std::vector<std::string>{"open"}));  // nothing to close
}

TEST(CameraDeviceDeathTest, StartBeforeOpenIsABug) {
  EXPECT_DEATH(
      {
        ScriptedDevice device(0);
        device.Start([](RgbdFrame&&) {});
      },
      "Start\\(\\) on scripted in state created");
}

TEST(CameraDevice, DeviceNsKeepsPrecisionForLargeCounts) {
  RgbdFrame frame;
  frame.ticks_per_second = 60e6;
  frame.depth_ticks = (int64_t{1} << 40) + 3;  // about 5 hours of unwrapped Kinect1 ticks
  const int64_t seconds = frame.depth_ticks / 60'000'000;
  const int64_t rest = frame.depth_ticks % 60'000'000;
  EXPECT_EQ(frame.depth_device_ns(), seconds * 1'000'000'000 + (rest * 50 + 1) / 3);
}

}  // namespace
}  // namespace mocap::capture
