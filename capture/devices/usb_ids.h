#pragma once
// What a USB vendor:product id is, for `mocaplabel devices`. Kept apart from the libusb enumeration so
// the table can be tested without hardware. Ids: libfreenect src/freenect_internal.h and
// platform/linux/udev/51-kinect.rules (Kinect1), libfreenect2 libfreenect2.hpp (Kinect2), and the usual
// USB-serial bridges that NDI Polaris/Aurora serial cables and adapters use.
#include <cstdint>
#include <string>

namespace mocap::capture {

enum class UsbDeviceKind {
  kKinect1Camera,   ///< Xbox 360 Kinect camera (045e:02ae) or Kinect for Windows camera (045e:02bf)
  kKinect1Motor,    ///< motor + accelerometer subdevice (045e:02b0)
  kKinect1Audio,    ///< audio subdevice
  kKinect2,         ///< Kinect v2 (045e:02d8, preview 045e:02c4)
  kUsbSerial,       ///< USB-serial bridge (FTDI, Prolific, Silicon Labs CP210x, WCH CH340)
  kOther,           ///< anything else: not listed
};

const char* ToString(UsbDeviceKind kind);

struct UsbDeviceClass {
  UsbDeviceKind kind = UsbDeviceKind::kOther;
  std::string description;  ///< e.g. "Kinect1 camera (Xbox 360)"; empty for kOther
};

UsbDeviceClass ClassifyUsb(uint16_t vendor_id, uint16_t product_id);

}  // namespace mocap::capture
