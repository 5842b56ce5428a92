#include <CLI/CLI.hpp>
#include <cstdio>

#include "capture/devices/device_scan.h"
#include "cli/parse_args.h"
#include "cli/commands.h"

namespace mocap::cli {

int RunDevices(int argc, char** argv) {
  CLI::App app{"List attached Kinects, USB-serial adapters, serial ports and reachable network trackers",
               "mocaplabel devices"};
  bool json = false;
  capture::DeviceScanOptions options;
  app.add_flag("--json", json, "print one JSON document");
  app.add_option("--tracker", options.trackers, "a network tracker to try, host:port (repeatable; NDI Vega: 8765)");
  app.add_option("--timeout-ms", options.connect_timeout_ms, "TCP connect timeout per tracker")
      ->capture_default_str();
  app.add_option("--dev-dir", options.dev_dir, "where to look for ttyUSB*/ttyACM* serial ports")
      ->capture_default_str();
  MOCAP_PARSE(app, argc, argv);
  const capture::DeviceReport report = capture::ScanDevices(options);
  if (json) {
    std::printf("%s\n", capture::ToJson(report).dump(2).c_str());
  } else {
    std::fputs(capture::ToText(report).c_str(), stdout);
  }
  return 0;
}

}  // namespace mocap::cli
