#pragma once
// The daemon's control API: HTTP + JSON (cpp-httplib, Debian's libcpp-httplib-dev) on 127.0.0.1 by
// default. Endpoints (docs/capture.md):
//   GET  /status                     -> 200 CaptureDaemon::Status()
//   POST /start  {"name": "S"}       -> 200 {"session", "dir", "state"}; 400 bad request; 409 recording
//   POST /stop                       -> 200 the session summary; 409 nothing to stop
//   GET  /, /live/...                -> the live page and its data (live_routes.h, docs/live-page.md)
// Every error is a JSON object {"error": "..."} with a 4xx/5xx status: 404 an unknown path, 405 (with
// Allow) a known path with another method, 413 a body over max_body_bytes (also chunked, or once
// decompressed), 400 JSON nested deeper than max_json_depth. Access: clients from loopback addresses
// only, unless allow_remote is set; binding to a non-loopback address requires allow_remote and a
// token, and then every request must carry "Authorization: Bearer <token>"; a browser, which cannot
// add that header to the page's requests, opens /?token=<token> once and then sends it as a cookie.
// A request whose Origin is not the daemon's own is refused (another web site's script in the
// operator's browser must not start or stop a session).
#include <cstddef>
#include <memory>
#include <string>
#include <thread>

#include "capture/daemon/daemon.h"
#include "capture/daemon/live_feed.h"

namespace httplib {
class Server;
}

namespace mocap::capture {

struct ControlServerOptions {
  std::string bind = "127.0.0.1";  ///< IPv4 address to listen on
  int port = 8780;                 ///< 0: any free port (see ControlServer::port())
  bool allow_remote = false;       ///< serve clients that are not on a loopback address
  std::string token{};              ///< required from every client when set (and with allow_remote)
  /// Request limits. A /start body is about 20 bytes; the limits keep a hostile or broken client from
  /// costing the recording daemon memory (a 10 MB '[[[...' body once cost 700 MB and 14 s).
  size_t max_body_bytes = 64 * 1024;  ///< larger bodies: 413, read and discarded, never stored
  int max_json_depth = 8;             ///< deeper JSON: 400 before parsing
  /// Connections. Each open connection holds a worker while it waits for a request, so idle or slow
  /// clients must not be able to occupy all workers (with cpp-httplib's 8, eight idle connections
  /// stalled the API for 5 s).
  int worker_threads = 64;        ///< connections served at once
  int idle_timeout_s = 1;         ///< a connection without a (next) request is closed after this
  int read_timeout_s = 5;         ///< a request that stops arriving mid-way is dropped after this
  /// Live page event streams at once. Each holds a worker of its own (on top of worker_threads) while
  /// it lasts; more are answered 503 and the page polls instead.
  int max_live_viewers = 128;
  LiveFeedOptions live_feed{};
  /// Throws InputError: a non-loopback bind without allow_remote, allow_remote without a token, or a
  /// limit that is not positive.
  void check() const;
};

/// The name of the cookie that carries the token for a browser.
inline constexpr const char* kTokenCookie = "mocaplabel_token";

/// 127.0.0.0/8, ::1 and ::ffff:127.x.
bool IsLoopbackAddress(const std::string& address);

/// Whether a request may be served: status 0 when it may, else the HTTP status and error to answer.
struct AccessDecision {
  int status = 0;
  std::string error;
};
AccessDecision CheckAccess(const ControlServerOptions& options, const std::string& remote_addr,
                           const std::string& authorization_header);

class ControlServer {
 public:
  /// Binds and starts serving on its own thread; throws InputError when the address cannot be bound.
  ControlServer(CaptureDaemon& daemon, const ControlServerOptions& options);
  ~ControlServer();  ///< stops serving
  ControlServer(const ControlServer&) = delete;
  ControlServer& operator=(const ControlServer&) = delete;

  int port() const { return port_; }
  void Stop();

 private:
  void AddRoutes();
  void WidenBacklog();
  CaptureDaemon& daemon_;
  ControlServerOptions options_;
  std::unique_ptr<LiveFeed> feed_;
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
  int port_ = 0;
  int listen_fd_ = -1;  ///< the listening socket, seen through httplib's socket-options hook
};

}  // namespace mocap::capture
