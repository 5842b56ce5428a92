#include "capture/devices/usb_ids.h"

#include <array>

namespace mocap::capture {
namespace {

struct KnownId {
  uint16_t vendor_id;
  uint16_t product_id;
  UsbDeviceKind kind;
  const char* description;
};

constexpr uint16_t kMicrosoft = 0x045e;

constexpr std::array kKnownIds = {
    KnownId{kMicrosoft, 0x02ae, UsbDeviceKind::kKinect1Camera, "Kinect1 camera (Xbox 360)"},
    KnownId{kMicrosoft, 0x02b0, UsbDeviceKind::kKinect1Motor, "Kinect1 motor/accelerometer (Xbox 360)"},
    KnownId{kMicrosoft, 0x02ad, UsbDeviceKind::kKinect1Audio, "Kinect1 audio (Xbox 360)"},
    KnownId{kMicrosoft, 0x02bf, UsbDeviceKind::kKinect1Camera, "Kinect for Windows camera"},
    KnownId{kMicrosoft, 0x02be, UsbDeviceKind::kKinect1Audio, "Kinect for Windows audio"},
    KnownId{kMicrosoft, 0x02c3, UsbDeviceKind::kKinect1Audio, "Kinect for Windows audio"},
    KnownId{kMicrosoft, 0x02bb, UsbDeviceKind::kKinect1Audio, "Kinect for Windows audio"},
    KnownId{kMicrosoft, 0x02c2, UsbDeviceKind::kKinect1Motor, "Kinect for Windows subdevice (in libfreenect udev rules; role unconfirmed)"},
    KnownId{kMicrosoft, 0x02d8, UsbDeviceKind::kKinect2, "Kinect2"},
    KnownId{kMicrosoft, 0x02c4, UsbDeviceKind::kKinect2, "Kinect2 (preview)"},
    KnownId{0x0403, 0x6001, UsbDeviceKind::kUsbSerial, "FTDI FT232R USB-serial"},
    KnownId{0x0403, 0x6015, UsbDeviceKind::kUsbSerial, "FTDI FT-X USB-serial"},
    KnownId{0x067b, 0x2303, UsbDeviceKind::kUsbSerial, "Prolific PL2303 USB-serial"},
    KnownId{0x10c4, 0xea60, UsbDeviceKind::kUsbSerial, "Silicon Labs CP210x USB-serial"},
    KnownId{0x1a86, 0x7523, UsbDeviceKind::kUsbSerial, "WCH CH340 USB-serial"},
};

}  // namespace

const char* ToString(UsbDeviceKind kind) {
  switch (kind) {
    case UsbDeviceKind::kKinect1Camera: return "kinect1_camera";
    case UsbDeviceKind::kKinect1Motor: return "kinect1_motor";
    case UsbDeviceKind::kKinect1Audio: return "kinect1_audio";
    case UsbDeviceKind::kKinect2: return "kinect2";
    case UsbDeviceKind::kUsbSerial: return "usb_serial";
    case UsbDeviceKind::kOther: return "other";
  }
  return "other";
}

UsbDeviceClass ClassifyUsb(uint16_t vendor_id, uint16_t product_id) {
  for (const KnownId& known : kKnownIds)
    if (known.vendor_id == vendor_id && known.product_id == product_id) return {known.kind, known.description};
  return {};
}

}  // namespace mocap::capture
