#pragma once
// Finds what a capture rig could use: Kinects and USB-serial adapters on USB (libusb-1.0), serial ports
// (/dev/ttyUSB*, /dev/ttyACM*), and network trackers given as host:port (a TCP connect with a timeout).
// A failed scan is a value in the report (e.g. no USB access in a container), never an exception.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "capture/devices/usb_ids.h"

namespace mocap::capture {

struct UsbDeviceEntry {
  uint16_t vendor_id = 0;
  uint16_t product_id = 0;
  int bus = 0;
  int address = 0;
  UsbDeviceClass device_class;
};

struct UsbScan {
  bool available = false;  ///< libusb could enumerate
  std::string error;       ///< why not, when not
  int devices_seen = 0;    ///< all USB devices, known or not
  std::vector<UsbDeviceEntry> known;  ///< the Kinects and USB-serial adapters among them
};

/// Enumerates the USB bus with libusb-1.0 and keeps the devices ClassifyUsb knows.
UsbScan ScanUsb();

/// ttyUSB* and ttyACM* under dev_dir, sorted.
std::vector<std::string> FindSerialPorts(const std::filesystem::path& dev_dir);

struct TrackerEndpoint {
  std::string host;
  int port = 0;
};

/// "host:port" (IPv6 as "[addr]:port"); throws InputError naming the text when malformed.
TrackerEndpoint ParseTrackerEndpoint(const std::string& text);

struct TrackerProbe {
  TrackerEndpoint endpoint;
  bool reachable = false;
  std::string detail;       ///< "connected", or why not (timeout, refused, unknown host)
  double connect_ms = 0.0;  ///< time to connect or to give up
};

/// One TCP connect to the endpoint, abandoned after timeout_ms.
TrackerProbe ProbeTracker(const TrackerEndpoint& endpoint, int timeout_ms);

struct DeviceScanOptions {
  std::vector<std::string> trackers;  ///< host:port of network trackers to try (NDI Vega: port 8765)
  int connect_timeout_ms = 500;
  std::filesystem::path dev_dir = "/dev";
  /// Throws InputError on a malformed tracker or a non-positive timeout.
  void check() const;
};

struct BackendStatus {
  bool built = false;
  std::string detail;
};

struct DeviceReport {
  UsbScan usb;
  std::vector<std::string> serial_ports;
  std::vector<TrackerProbe> trackers;
  BackendStatus kinect1;
  BackendStatus kinect2;
  /// No Kinect, USB-serial adapter, serial port or reachable tracker.
  bool NothingFound() const;
};

DeviceReport ScanDevices(const DeviceScanOptions& options);

nlohmann::json ToJson(const DeviceReport& report);
/// The human-readable listing, ending with a clear "none found" line when nothing was found.
std::string ToText(const DeviceReport& report);

}  // namespace mocap::capture
