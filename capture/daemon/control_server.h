#pragma once
// The daemon's control API: HTTP + JSON (cpp-httplib, Debian's libcpp-httplib-dev) on 127.0.0.1 by
// default. Endpoints (docs/capture.md):
//   GET  /status                     -> 200 CaptureDaemon::Status()
//   POST /start  {"name": "S"}       -> 200 {"session", "dir", "state"}; 400 bad request; 409 recording
//   POST /stop                       -> 200 the session summary; 409 nothing to stop
// Every error is a JSON object {"error": "..."} with a 4xx/5xx status. Access: clients from loopback
// addresses only, unless allow_remote is set; binding to a non-loopback address requires allow_remote
// and a token, and then every request must carry "Authorization: Bearer <token>".
#include <memory>
#include <string>
#include <thread>

#include "capture/daemon/daemon.h"

namespace httplib {
class Server;
}

namespace mocap::capture {

struct ControlServerOptions {
  std::string bind = "127.0.0.1";  ///< IPv4 address to listen on
  int port = 8780;                 ///< 0: any free port (see ControlServer::port())
  bool allow_remote = false;       ///< serve clients that are not on a loopback address
  std::string token{};              ///< required from every client when set (and with allow_remote)
  /// Throws InputError: a non-loopback bind without allow_remote, or allow_remote without a token.
  void check() const;
};

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
  CaptureDaemon& daemon_;
  ControlServerOptions options_;
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
  int port_ = 0;
};

}  // namespace mocap::capture
