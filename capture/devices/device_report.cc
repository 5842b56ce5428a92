#include <sstream>

#include "capture/devices/device_scan.h"
#include "capture/kinect/kinect1_device.h"
#include "capture/kinect/kinect2_support.h"
#include "core/check.h"

namespace mocap::capture {
namespace {

std::string HexId(uint16_t vendor_id, uint16_t product_id) {
  char text[16];
  std::snprintf(text, sizeof(text), "%04x:%04x", vendor_id, product_id);
  return text;
}

std::string Endpoint(const TrackerEndpoint& endpoint) {
  return endpoint.host + ":" + std::to_string(endpoint.port);
}

}  // namespace

void DeviceScanOptions::check() const {
  if (connect_timeout_ms <= 0) throw InputError("--timeout-ms", "must be positive");
  for (const std::string& tracker : trackers) ParseTrackerEndpoint(tracker);
}

bool DeviceReport::NothingFound() const {
  for (const TrackerProbe& probe : trackers)
    if (probe.reachable) return false;
  return usb.known.empty() && serial_ports.empty();
}

DeviceReport ScanDevices(const DeviceScanOptions& options) {
  options.check();
  DeviceReport report;
  report.usb = ScanUsb();
  report.serial_ports = FindSerialPorts(options.dev_dir);
  for (const std::string& tracker : options.trackers)
    report.trackers.push_back(ProbeTracker(ParseTrackerEndpoint(tracker), options.connect_timeout_ms));
  report.kinect1 = {true, Kinect1SupportDetail()};
  report.kinect2 = {Kinect2SupportBuilt(), Kinect2SupportDetail()};
  return report;
}

nlohmann::json ToJson(const DeviceReport& report) {
  nlohmann::json usb_devices = nlohmann::json::array();
  for (const UsbDeviceEntry& d : report.usb.known)
    usb_devices.push_back({{"id", HexId(d.vendor_id, d.product_id)},
                           {"kind", ToString(d.device_class.kind)},
                           {"description", d.device_class.description},
                           {"bus", d.bus},
                           {"address", d.address}});
  nlohmann::json trackers = nlohmann::json::array();
  for (const TrackerProbe& t : report.trackers)
    trackers.push_back({{"endpoint", Endpoint(t.endpoint)},
                        {"reachable", t.reachable},
                        {"detail", t.detail},
                        {"connect_ms", t.connect_ms}});
  return {{"usb",
           {{"available", report.usb.available},
            {"error", report.usb.error},
            {"devices_seen", report.usb.devices_seen},
            {"devices", usb_devices}}},
          {"serial_ports", report.serial_ports},
          {"trackers", trackers},
          {"support",
           {{"kinect1", {{"built", report.kinect1.built}, {"detail", report.kinect1.detail}}},
            {"kinect2", {{"built", report.kinect2.built}, {"detail", report.kinect2.detail}}}}},
          {"none_found", report.NothingFound()}};
}

std::string ToText(const DeviceReport& report) {
  std::ostringstream out;
  out << "Kinect1 support: " << report.kinect1.detail << "\n";
  out << "Kinect2 support: " << report.kinect2.detail << "\n";
  if (!report.usb.available) {
    out << "USB: not scanned: " << report.usb.error << "\n";
  } else {
    out << "USB: " << report.usb.devices_seen << " devices seen, " << report.usb.known.size() << " of use\n";
    for (const UsbDeviceEntry& d : report.usb.known)
      out << "  " << HexId(d.vendor_id, d.product_id) << "  " << d.device_class.description << "  (bus " << d.bus
          << ", address " << d.address << ")\n";
  }
  out << "Serial ports: " << (report.serial_ports.empty() ? "none" : "") << "\n";
  for (const std::string& port : report.serial_ports) out << "  " << port << "\n";
  if (!report.trackers.empty()) out << "Network trackers:\n";
  for (const TrackerProbe& t : report.trackers)
    out << "  " << Endpoint(t.endpoint) << "  " << (t.reachable ? "reachable" : "unreachable: ") 
        << (t.reachable ? "" : t.detail) << "\n";
  if (report.NothingFound())
    out << "none found: no Kinect, USB-serial adapter, serial port or reachable network tracker"
        << (report.usb.available ? "" : " (USB could not be scanned)") << "\n";
  return out.str();
}

}  // namespace mocap::capture
