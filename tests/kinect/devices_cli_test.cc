// `mocaplabel devices` as a user runs it: the text and the JSON agree, "none found" is said when nothing
// is attached, and a listening TCP port given as --tracker is reported reachable (a closed one is not).
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "subprocess.h"

namespace mocap::capture {
namespace {

namespace fs = std::filesystem;

testing::ProcessResult Devices(std::vector<std::string> args) {
  args.insert(args.begin(), {MOCAPLABEL_EXE, "devices", "--dev-dir", "/nonexistent-dev"});
  // One log per run: ctest may run these tests in parallel.
  static int runs = 0;
  const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  const fs::path log = fs::path(MOCAP_BINARY_DIR) / "test_output" / "kinect" /
                       ("devices_cli_" + test + "_" + std::to_string(runs++) + ".log");
  fs::create_directories(log.parent_path());
  return testing::RunProcess(args, {}, log);
}

// A loopback listener on an ephemeral port; closed when the test ends.
struct Listener {
  int fd = -1;
  int port = 0;
  Listener() {
    fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address));
    listen(fd, 4);
    socklen_t length = sizeof(address);
    getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
    port = ntohs(address.sin_port);
  }
  ~Listener() { close(fd); }
};

// A loopback port nobody listens on: bound, then closed.
int ClosedPort() {
  const Listener listener;
  return listener.port;
}

TEST(DevicesCli, TextAndJsonAgreeAndSayNoneFound) {
  const auto text = Devices({});
  ASSERT_EQ(text.exit_code, 0) << text.output;
  const auto json_run = Devices({"--json"});
  ASSERT_EQ(json_run.exit_code, 0) << json_run.output;
  const nlohmann::json doc = nlohmann::json::parse(json_run.output);  // stdout is exactly one document
  const bool none_found = doc.at("none_found").get<bool>();
  EXPECT_EQ(none_found, doc.at("usb").at("devices").empty() && doc.at("serial_ports").empty());
  EXPECT_EQ(text.output.find("none found") != std::string::npos, none_found) << text.output;
  EXPECT_FALSE(doc.at("support").at("kinect2").at("detail").get<std::string>().empty());
  EXPECT_NE(text.output.find("Kinect2 support: "), std::string::npos);
  // This build machine has no Kinect or serial adapter attached (and, in a container, often no USB).
  EXPECT_TRUE(none_found) << text.output;
}

TEST(DevicesCli, ProbesNetworkTrackers) {
  Listener listener;
  ASSERT_GT(listener.port, 0);
  const int dead_port = ClosedPort();
  const auto run = Devices({"--json", "--tracker", "127.0.0.1:" + std::to_string(listener.port), "--tracker",
                            "127.0.0.1:" + std::to_string(dead_port), "--timeout-ms", "300"});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json doc = nlohmann::json::parse(run.output);
  ASSERT_EQ(doc.at("trackers").size(), 2u);
  EXPECT_TRUE(doc.at("trackers")[0].at("reachable").get<bool>());
  EXPECT_FALSE(doc.at("trackers")[1].at("reachable").get<bool>());
  EXPECT_NE(doc.at("trackers")[1].at("detail").get<std::string>().find("refused"), std::string::npos);
  EXPECT_FALSE(doc.at("none_found").get<bool>());
}

TEST(DevicesCli, MalformedTrackerIsOneClearLine) {
  const auto run = Devices({"--tracker", "vega-without-port"});
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("expected host:port"), std::string::npos) << run.output;
  EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
}

}  // namespace
}  // namespace mocap::capture
