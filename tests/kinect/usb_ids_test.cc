#include "capture/devices/usb_ids.h"

#include <gtest/gtest.h>

#include <fstream>

#include "capture/devices/device_scan.h"
#include "core/check.h"

namespace mocap::capture {
namespace {

struct IdCase {
  uint16_t vendor_id;
  uint16_t product_id;
  UsbDeviceKind kind;
};

TEST(UsbIds, ClassifiesTheKnownIds) {
  const IdCase cases[] = {
      {0x045e, 0x02ae, UsbDeviceKind::kKinect1Camera}, {0x045e, 0x02bf, UsbDeviceKind::kKinect1Camera},
      {0x045e, 0x02b0, UsbDeviceKind::kKinect1Motor},  {0x045e, 0x02ad, UsbDeviceKind::kKinect1Audio},
      {0x045e, 0x02be, UsbDeviceKind::kKinect1Audio},  {0x045e, 0x02d8, UsbDeviceKind::kKinect2},
      {0x045e, 0x02c4, UsbDeviceKind::kKinect2},       {0x0403, 0x6001, UsbDeviceKind::kUsbSerial},
      {0x0403, 0x6015, UsbDeviceKind::kUsbSerial},     {0x067b, 0x2303, UsbDeviceKind::kUsbSerial},
      {0x10c4, 0xea60, UsbDeviceKind::kUsbSerial},     {0x1a86, 0x7523, UsbDeviceKind::kUsbSerial},
      // Near misses: another Microsoft device, the FTDI vendor with another product, Kinect PID elsewhere.
      {0x045e, 0x0745, UsbDeviceKind::kOther},         {0x0403, 0x6010, UsbDeviceKind::kOther},
      {0x1d6b, 0x02ae, UsbDeviceKind::kOther},         {0x0000, 0x0000, UsbDeviceKind::kOther},
  };
  for (const IdCase& c : cases) {
    const UsbDeviceClass got = ClassifyUsb(c.vendor_id, c.product_id);
    EXPECT_EQ(got.kind, c.kind) << std::hex << c.vendor_id << ":" << c.product_id;
    EXPECT_EQ(got.description.empty(), c.kind == UsbDeviceKind::kOther);
  }
}

TEST(TrackerEndpoint, ParsesHostAndPort) {
  const TrackerEndpoint vega = ParseTrackerEndpoint("192.168.1.20:8765");
  EXPECT_EQ(vega.host, "192.168.1.20");
  EXPECT_EQ(vega.port, 8765);
  EXPECT_EQ(ParseTrackerEndpoint("[::1]:8765").host, "::1");
  for (const char* bad : {"8765", "host:", ":8765", "host:0", "host:70000", "host:87a"})
    EXPECT_THROW(ParseTrackerEndpoint(bad), InputError) << bad;
}

TEST(SerialPorts, FindsUsbAndAcmTtys) {
  const auto dir = std::filesystem::path(MOCAP_BINARY_DIR) / "test_output" / "kinect" / "fake_dev";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  for (const char* name : {"ttyUSB1", "ttyACM0", "ttyS0", "ttyUSB0", "null"})
    std::ofstream(dir / name) << "";
  EXPECT_EQ(FindSerialPorts(dir), (std::vector<std::string>{(dir / "ttyACM0").string(), (dir / "ttyUSB0").string(),
                                                            (dir / "ttyUSB1").string()}));
  EXPECT_TRUE(FindSerialPorts(dir / "absent").empty());
}

}  // namespace
}  // namespace mocap::capture
