// The control API: who may talk to it, and clear errors for malformed requests.
#include <gtest/gtest.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <arpa/inet.h>

#include "capture/daemon/control_server.h"
#include "capture/daemon/sources.h"
#include "core/check.h"
#include "test_dirs.h"
// Last: it pulls in <resolv.h>, whose `_res` macro breaks Eigen headers included after it.
#include <httplib.h>

namespace mocap::capture {
namespace {

namespace fs = std::filesystem;

TEST(ControlAccess, LoopbackOnlyUnlessConfigured) {
  const ControlServerOptions local;
  EXPECT_EQ(CheckAccess(local, "127.0.0.1", "").status, 0);
  EXPECT_EQ(CheckAccess(local, "127.4.5.6", "").status, 0);
  EXPECT_EQ(CheckAccess(local, "::1", "").status, 0);
  EXPECT_EQ(CheckAccess(local, "::ffff:127.0.0.1", "").status, 0);
  const AccessDecision refused = CheckAccess(local, "192.168.1.20", "");
  EXPECT_EQ(refused.status, 403);
  EXPECT_NE(refused.error.find("--allow-remote"), std::string::npos) << refused.error;
  EXPECT_EQ(CheckAccess(local, "::ffff:10.0.0.1", "").status, 403);

  const ControlServerOptions remote{.bind = "0.0.0.0", .allow_remote = true, .token = "s3cret"};
  EXPECT_EQ(CheckAccess(remote, "192.168.1.20", "").status, 401);
  EXPECT_EQ(CheckAccess(remote, "192.168.1.20", "Bearer wrong").status, 401);
  EXPECT_EQ(CheckAccess(remote, "192.168.1.20", "Bearer s3cret").status, 0);
  EXPECT_EQ(CheckAccess(remote, "127.0.0.1", "").status, 401);  // a token binds loopback clients too
}

TEST(ControlAccess, BindingElsewhereNeedsAllowRemoteAndAToken) {
  EXPECT_NO_THROW((ControlServerOptions{}.check()));
  EXPECT_THROW((ControlServerOptions{.bind = "0.0.0.0"}.check()), InputError);
  EXPECT_THROW((ControlServerOptions{.bind = "0.0.0.0", .allow_remote = true}.check()), InputError);
  EXPECT_NO_THROW((ControlServerOptions{.bind = "0.0.0.0", .allow_remote = true, .token = "t"}.check()));
  EXPECT_THROW((ControlServerOptions{.bind = "localhost"}.check()), InputError);  // an address, not a name
  EXPECT_THROW((ControlServerOptions{.port = 70000}.check()), InputError);
}

struct Fixture {
  explicit Fixture(const std::string& name, const ControlServerOptions& control = {.port = 0}) {
    std::vector<std::unique_ptr<CaptureSource>> sources;
    sources.push_back(CreateSimulatedTracker({.stream = "trk", .bodies = 1, .rate_hz = 100}));
    daemon = std::make_unique<CaptureDaemon>(CaptureDaemonOptions{.sessions_dir = testing::FreshCaptureDir(name)},
                                             std::move(sources));
    server = std::make_unique<ControlServer>(*daemon, control);
  }
  std::unique_ptr<CaptureDaemon> daemon;
  std::unique_ptr<ControlServer> server;
};

std::string ErrorOf(const httplib::Result& result) {
  return nlohmann::json::parse(result->body).value("error", std::string());
}

TEST(ControlApi, MalformedRequestsGetClearErrors) {
  Fixture f("api_malformed");
  httplib::Client client("127.0.0.1", f.server->port());
  auto r = client.Post("/start", "{name: bad json", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(ErrorOf(r).find("is not JSON"), std::string::npos) << r->body;
  r = client.Post("/start", R"({"session": "x"})", "application/json");
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(ErrorOf(r).find("\"name\""), std::string::npos) << r->body;
  r = client.Post("/start", R"({"name": 5})", "application/json");
  EXPECT_EQ(r->status, 400);
  r = client.Post("/start", R"({"name": "a/b"})", "application/json");
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(ErrorOf(r).find("may only hold"), std::string::npos) << r->body;
  r = client.Post("/start", R"({"name": "ok", "extra": 1})", "application/json");
  EXPECT_EQ(r->status, 400);
  r = client.Get("/start");
  EXPECT_EQ(r->status, 405);
  r = client.Get("/nowhere");
  EXPECT_EQ(r->status, 404);
  EXPECT_NE(ErrorOf(r).find("no such endpoint"), std::string::npos) << r->body;
  r = client.Post("/stop", "", "application/json");
  EXPECT_EQ(r->status, 409);
  EXPECT_NE(ErrorOf(r).find("no session"), std::string::npos) << r->body;
}

TEST(ControlApi, StartStatusStop) {
  Fixture f("api_session");
  httplib::Client client("127.0.0.1", f.server->port());
  auto r = client.Post("/start", R"({"name": "S1"})", "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  r = client.Post("/start", R"({"name": "S2"})", "application/json");
  EXPECT_EQ(r->status, 409);
  r = client.Get("/status");
  ASSERT_EQ(r->status, 200);
  const nlohmann::json status = nlohmann::json::parse(r->body);
  EXPECT_EQ(status["state"], "recording");
  EXPECT_EQ(status["session"]["name"], "S1");
  r = client.Post("/stop", "", "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(nlohmann::json::parse(r->body)["complete"], true);
}

// A non-loopback IPv4 address of this machine, if it has one.
std::optional<std::string> NonLoopbackAddress() {
  ifaddrs* list = nullptr;
  if (::getifaddrs(&list) != 0) return std::nullopt;
  std::optional<std::string> found;
  for (ifaddrs* a = list; a && !found; a = a->ifa_next) {
    if (!a->ifa_addr || a->ifa_addr->sa_family != AF_INET) continue;
    char text[INET_ADDRSTRLEN];
    ::inet_ntop(AF_INET, &reinterpret_cast<sockaddr_in*>(a->ifa_addr)->sin_addr, text, sizeof(text));
    if (!IsLoopbackAddress(text)) found = text;
  }
  ::freeifaddrs(list);
  return found;
}

TEST(ControlApi, RemoteClientsNeedTheToken) {
  const std::optional<std::string> address = NonLoopbackAddress();
  if (!address) GTEST_SKIP() << "no non-loopback IPv4 address on this machine";
  Fixture f("api_remote", {.bind = "0.0.0.0", .port = 0, .allow_remote = true, .token = "s3cret"});
  httplib::Client client(*address, f.server->port());
  auto r = client.Get("/status");
  ASSERT_TRUE(r) << "cannot connect to " << *address;
  EXPECT_EQ(r->status, 401);
  r = client.Get("/status", {{"Authorization", "Bearer s3cret"}});
  EXPECT_EQ(r->status, 200);
}

}  // namespace
}  // namespace mocap::capture
