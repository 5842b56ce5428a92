// USB enumeration with libusb-1.0 and the serial ports the kernel made for USB-serial adapters.
#include <libusb.h>

#include <algorithm>
#include <system_error>

#include "capture/devices/device_scan.h"

namespace mocap::capture {

UsbScan ScanUsb() {
  UsbScan scan;
  libusb_context* context = nullptr;
  if (const int rc = libusb_init(&context); rc < 0) {
    scan.error = std::string("libusb cannot start: ") + libusb_strerror(static_cast<libusb_error>(rc)) +
                 " (no /dev/bus/usb in this container or VM?)";
    return scan;
  }
  libusb_device** list = nullptr;
  const ssize_t count = libusb_get_device_list(context, &list);
  if (count < 0) {
    scan.error = std::string("libusb cannot list devices: ") + libusb_strerror(static_cast<libusb_error>(count));
    libusb_exit(context);
    return scan;
  }
  scan.devices_seen = static_cast<int>(count);
  scan.available = count > 0 || std::filesystem::exists("/dev/bus/usb");
  if (!scan.available) scan.error = "no /dev/bus/usb: this system (a container or VM?) exposes no USB devices";
  for (ssize_t i = 0; i < count; ++i) {
    libusb_device_descriptor descriptor{};
    if (libusb_get_device_descriptor(list[i], &descriptor) < 0) continue;
    UsbDeviceClass device_class = ClassifyUsb(descriptor.idVendor, descriptor.idProduct);
    if (device_class.kind == UsbDeviceKind::kOther) continue;
    scan.known.push_back({descriptor.idVendor, descriptor.idProduct, libusb_get_bus_number(list[i]),
                          libusb_get_device_address(list[i]), std::move(device_class)});
  }
  libusb_free_device_list(list, 1);
  libusb_exit(context);
  return scan;
}

std::vector<std::string> FindSerialPorts(const std::filesystem::path& dev_dir) {
  std::vector<std::string> ports;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(dev_dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("ttyUSB", 0) == 0 || name.rfind("ttyACM", 0) == 0) ports.push_back(entry.path().string());
  }
  std::sort(ports.begin(), ports.end());
  return ports;
}

}  // namespace mocap::capture
