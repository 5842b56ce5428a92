// The control API: who may talk to it, and clear errors for malformed requests.
#include <gtest/gtest.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <regex>
#include <thread>

#include "capture/daemon/control_server.h"
#include "capture/daemon/json_depth.h"
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
    daemon_sessions = testing::FreshCaptureDir(name);
    daemon = std::make_unique<CaptureDaemon>(CaptureDaemonOptions{.sessions_dir = daemon_sessions},
                                             std::move(sources));
    server = std::make_unique<ControlServer>(*daemon, control);
  }
  fs::path daemon_sessions;
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
  // The session says which mocaplabel wrote it (CMake's PROJECT_VERSION, e.g. 0.1.0).
  const nlohmann::json manifest = nlohmann::json::parse(std::ifstream(f.daemon_sessions / "S1" / "manifest.json"));
  EXPECT_TRUE(std::regex_match(manifest.value("software_version", std::string()), std::regex(R"(\d+\.\d+\.\d+.*)")))
      << manifest.dump();
}

// Every known path answers 405 with an Allow header for another method; unknown paths 404; both JSON.
TEST(ControlApi, WrongMethodsAre405AndUnknownPaths404) {
  Fixture f("api_methods");
  httplib::Client client("127.0.0.1", f.server->port());
  const auto expect_405 = [](const httplib::Result& r, const std::string& allow) {
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 405) << r->body;
    EXPECT_EQ(r->get_header_value("Allow"), allow);
    EXPECT_NE(ErrorOf(r).find("use " + allow), std::string::npos) << r->body;
  };
  expect_405(client.Delete("/status"), "GET, HEAD");
  expect_405(client.Post("/status", "", "application/json"), "GET, HEAD");
  expect_405(client.Put("/status", "{}", "application/json"), "GET, HEAD");
  expect_405(client.Patch("/status", "{}", "application/json"), "GET, HEAD");
  expect_405(client.Options("/status"), "GET, HEAD");
  expect_405(client.Put("/stop", "", "application/json"), "POST");
  expect_405(client.Delete("/stop"), "POST");
  expect_405(client.Get("/stop"), "POST");
  expect_405(client.Get("/start"), "POST");
  expect_405(client.Put("/start", R"({"name": "S"})", "application/json"), "POST");
  for (const httplib::Result& r : {client.Delete("/nowhere"), client.Put("/nowhere", "{}", "application/json"),
                                   client.Post("/status/x", "", "application/json")}) {
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 404) << r->body;
    EXPECT_NE(ErrorOf(r).find("no such endpoint"), std::string::npos) << r->body;
  }
  const auto head = client.Head("/status");
  ASSERT_TRUE(head);
  EXPECT_EQ(head->status, 200);
  EXPECT_EQ(f.daemon->Status()["state"], "idle");
}

// A huge body is refused by its Content-Length (read and discarded, never stored or parsed), and a
// deeply nested one before the JSON parser sees it: once, 10 MB of '[' cost 700 MB and 14 s.
TEST(ControlApi, OversizedAndDeeplyNestedBodiesAreRefusedCheaply) {
  Fixture f("api_limits");
  httplib::Client client("127.0.0.1", f.server->port());
  client.set_read_timeout(30);
  ASSERT_EQ(client.Post("/start", R"({"name": "S1"})", "application/json")->status, 200);  // while recording
  const auto started = std::chrono::steady_clock::now();
  auto r = client.Post("/start", std::string(10'000'000, '['), "application/json");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  ASSERT_TRUE(r) << httplib::to_string(r.error());
  EXPECT_EQ(r->status, 413) << r->body;
  EXPECT_NE(ErrorOf(r).find("larger than 65536 bytes"), std::string::npos) << r->body;
  EXPECT_LT(seconds, 5.0);  // the 10 MB are only sent over loopback and discarded

  httplib::Client again("127.0.0.1", f.server->port());
  r = again.Post("/start", std::string(60'000, '['), "application/json");  // under the size limit
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400) << r->body;
  EXPECT_NE(ErrorOf(r).find("nests deeper than 8 levels"), std::string::npos) << r->body;
  r = again.Post("/start", R"({"name": "a[[[[[[[[[[[[b"})", "application/json");  // brackets in a string are data
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(ErrorOf(r).find("may only hold"), std::string::npos) << r->body;

  // A chunked body has no length to check up front, and a gzip one could inflate past it: both are
  // read through the same bound (after decompression).
  r = again.Post("/start", [](size_t, httplib::DataSink& sink) {
    sink.write("{\"name\": \"S2\"}", 14);
    sink.done();
    return true;
  }, "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 409) << r->body;  // read and parsed: S1 is recording
  r = again.Post("/stop", [](size_t offset, httplib::DataSink& sink) {
    const std::string chunk(16 * 1024, ' ');
    if (offset < 200'000) sink.write(chunk.data(), chunk.size());  // 200 KB of spaces, chunked
    else sink.done();
    return true;
  }, "application/json");
  if (r) {  // the server may close while the rest is still being sent
    EXPECT_EQ(r->status, 413) << r->body;
    EXPECT_NE(ErrorOf(r).find("larger than 65536 bytes"), std::string::npos) << r->body;
  }
  httplib::Client gzip("127.0.0.1", f.server->port());
  r = gzip.Post("/start", {{"Content-Encoding", "gzip"}}, "not gzip", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400) << r->body;
  EXPECT_EQ(f.daemon->Status()["session"]["name"], "S1");  // still recording the first session
}

TEST(JsonNestingDepth, CountsBracketsOutsideStrings) {
  EXPECT_EQ(JsonNestingDepth("5", 8), 0);
  EXPECT_EQ(JsonNestingDepth(R"({"a": [1, {"b": []}]})", 8), 4);
  EXPECT_EQ(JsonNestingDepth(R"({"a": "[[[{{{\"[[["})", 8), 1);
  EXPECT_EQ(JsonNestingDepth("[[[[[[[[[[[[", 3), 4);  // stops at the first level past the limit
  EXPECT_EQ(JsonNestingDepth("]]][", 8), 1);
}

// A TCP connection to the control port; optionally sends the start of a request and then nothing.
class RawConnection {
 public:
  RawConnection(int port, const std::string& partial_request) : fd_(::socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0;
    if (connected_ && !partial_request.empty())
      connected_ = ::send(fd_, partial_request.data(), partial_request.size(), 0) ==
                   static_cast<ssize_t>(partial_request.size());
  }
  ~RawConnection() { ::close(fd_); }
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;
  bool connected() const { return connected_; }

 private:
  int fd_;
  bool connected_ = false;
};

// Idle and slow clients hold a worker each; with cpp-httplib's default 8 workers and 5 s keep-alive,
// eight of them stalled `status` and `stop` for 5 s.
TEST(ControlApi, IdleAndSlowConnectionsDoNotBlockTheApi) {
  Fixture f("api_idle");
  std::vector<std::unique_ptr<RawConnection>> idle;
  for (int i = 0; i < 16; ++i) {
    idle.push_back(std::make_unique<RawConnection>(f.server->port(), i % 2 ? "GET /status HTTP/1.1\r\nHost: x" : ""));
    ASSERT_TRUE(idle.back()->connected());
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // let the server accept them all
  httplib::Client client("127.0.0.1", f.server->port());
  client.set_read_timeout(10);
  const auto started = std::chrono::steady_clock::now();
  auto r = client.Get("/status");
  ASSERT_TRUE(r) << httplib::to_string(r.error());
  EXPECT_EQ(r->status, 200);
  r = client.Post("/stop", "", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 409);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  EXPECT_LT(seconds, 1.0) << "the control API waited for idle connections";
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
