#include "capture/daemon/control_server.h"

#include <arpa/inet.h>
#include <sys/socket.h>

#include <cerrno>
#include <optional>
#include <system_error>

#include "capture/daemon/json_depth.h"
#include "capture/daemon/live_routes.h"
#include "core/check.h"
// Last: it pulls in <resolv.h>, whose `_res` macro breaks Eigen headers included after it.
#include <httplib.h>

namespace mocap::capture {

void ControlServerOptions::check() const {
  in_addr parsed{};
  if (::inet_pton(AF_INET, bind.c_str(), &parsed) != 1)
    throw InputError("control bind '" + bind + "'", "is not an IPv4 address (e.g. 127.0.0.1)");
  if (port < 0 || port > 65535) throw InputError("control port", Str(port, " is not in 0..65535"));
  if (!IsLoopbackAddress(bind) && !allow_remote)
    throw InputError("control bind '" + bind + "'",
                     "is not a loopback address: pass --allow-remote and a token (--token-file) to serve other hosts");
  if (allow_remote && token.empty())
    throw InputError("--allow-remote", "needs a token (--token-file F, $MOCAPLABEL_TOKEN or --token T): remote clients must authenticate");
  live_feed.check();
  if (max_live_viewers < 1) throw InputError("control limits", Str("max_live_viewers ", max_live_viewers, " must be positive"));
  if (max_body_bytes == 0 || max_json_depth < 1 || worker_threads < 1 || idle_timeout_s < 1 || read_timeout_s < 1)
    throw InputError("control limits", Str("must be positive (max_body_bytes ", max_body_bytes, ", max_json_depth ",
                                           max_json_depth, ", worker_threads ", worker_threads, ", idle_timeout_s ",
                                           idle_timeout_s, ", read_timeout_s ", read_timeout_s, ")"));
}

bool IsLoopbackAddress(const std::string& address) {
  if (address == "::1") return true;
  const std::string v4 = address.rfind("::ffff:", 0) == 0 ? address.substr(7) : address;
  in_addr parsed{};
  if (::inet_pton(AF_INET, v4.c_str(), &parsed) != 1) return false;
  return (ntohl(parsed.s_addr) >> 24) == 127;
}

AccessDecision CheckAccess(const ControlServerOptions& options, const std::string& remote_addr,
                           const std::string& authorization_header) {
  if (!options.allow_remote && !IsLoopbackAddress(remote_addr))
    return {403, "control API: clients from " + remote_addr +
                     " are refused (loopback only; start the daemon with --allow-remote and a token)"};
  if (!options.token.empty() && authorization_header != "Bearer " + options.token)
    return {401, "control API: missing or wrong token (send 'Authorization: Bearer <token>')"};
  return {};
}

namespace {

void Reply(httplib::Response& res, int status, const nlohmann::json& body) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

void ReplyError(httplib::Response& res, int status, const std::string& error) { Reply(res, status, {{"error", error}}); }

// The session name of a /start body: {"name": "..."} and nothing else that we would ignore silently.
std::string SessionNameFromBody(const std::string& body, int max_json_depth) {
  if (JsonNestingDepth(body, max_json_depth) > max_json_depth)
    throw InputError("POST /start body", Str("nests deeper than ", max_json_depth, " levels; send {\"name\": \"SESSION\"}"));
  nlohmann::json request;
  try {
    request = nlohmann::json::parse(body);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError("POST /start body", Str("is not JSON (", e.what(), "); send {\"name\": \"SESSION\"}"));
  }
  if (!request.is_object() || !request.contains("name") || !request["name"].is_string())
    throw InputError("POST /start body", "needs a string field \"name\": {\"name\": \"SESSION\"}");
  for (const auto& [key, value] : request.items())
    if (key != "name") throw InputError("POST /start body", "unknown field \"" + key + "\"");
  return request["name"].get<std::string>();
}

// Runs a handler, mapping the daemon's exceptions onto HTTP statuses.
template <typename Fn>
void Guarded(httplib::Response& res, Fn&& fn) {
  try {
    Reply(res, 200, fn());
  } catch (const StateError& e) {
    ReplyError(res, 409, e.what());
  } catch (const InputError& e) {
    ReplyError(res, 400, e.what());
  } catch (const std::exception& e) {
    ReplyError(res, 500, e.what());
  }
}

}  // namespace

ControlServer::ControlServer(CaptureDaemon& daemon, const ControlServerOptions& options)
    : daemon_(daemon), options_(options), server_(std::make_unique<httplib::Server>()) {
  options_.check();
  feed_ = std::make_unique<LiveFeed>(daemon_, options_.live_feed);
  AddRoutes();
  if (options_.port == 0) {
    port_ = server_->bind_to_any_port(options_.bind);
    if (port_ < 0) throw InputError("control " + options_.bind, "cannot bind any port");
  } else {
    if (!server_->bind_to_port(options_.bind, options_.port))
      throw InputError(Str("control ", options_.bind, ":", options_.port),
                       "cannot bind (in use? another daemon running?): choose another port");
    port_ = options_.port;
  }
  WidenBacklog();
  thread_ = std::thread([this] { server_->listen_after_bind(); });
  // The socket is bound and listening already (connections wait in its backlog); this only makes
  // Stop() right after construction well defined.
  while (!server_->is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

ControlServer::~ControlServer() { Stop(); }

// Debian's cpp-httplib is a shared library built with a listen backlog of 5 (its
// CPPHTTPLIB_LISTEN_BACKLOG cannot be changed from here). A page opening its event stream and image
// connections while others do the same overflowed it: the kernel dropped the handshakes, clients
// retried a second later, and some waited past their read timeout without a snapshot. listen() again
// on the bound socket widens the queue in place (Linux's listen(2)); the kernel caps it at
// net.core.somaxconn.
void ControlServer::WidenBacklog() {
  const std::string where = Str("control ", options_.bind, ":", port_);
  if (listen_fd_ < 0) throw InputError(where, "no listening socket was seen");
  if (::listen(listen_fd_, SOMAXCONN) != 0)
    throw InputError(where, "cannot widen the listen backlog: " + std::generic_category().message(errno));
}

void ControlServer::Stop() {
  if (feed_) feed_->Stop();  // ends the event streams, which would hold their workers
  if (server_) server_->stop();
  if (thread_.joinable()) thread_.join();
}

namespace {

// The endpoints and their methods: anything else on these paths is 405, any other path 404.
const char* AllowedMethods(const std::string& path) {
  if (path == "/status" || IsLivePath(path)) return "GET, HEAD";
  if (path == "/start" || path == "/stop") return "POST";
  return nullptr;
}

bool MethodAllowed(const std::string& path, const std::string& method) {
  if (path == "/status" || IsLivePath(path)) return method == "GET" || method == "HEAD";
  if (path == "/start" || path == "/stop") return method == "POST";
  return false;
}

// A request body of at most max_bytes (after decompression), read through cpp-httplib's content
// reader: its own limit covers only Content-Length, not chunked transfer or an inflating gzip body.
// nullopt when it is larger (res.status 413) or cannot be read (res.status 4xx).
std::optional<std::string> ReadBoundedBody(const httplib::ContentReader& reader, size_t max_bytes, httplib::Response& res) {
  std::string body;
  bool too_large = false;
  const bool read = reader([&](const char* data, size_t size) {
    if (body.size() + size > max_bytes) return !(too_large = true);
    body.append(data, size);
    return true;
  });
  if (too_large) res.status = 413;
  if (read && !too_large) return body;
  if (res.status < 400) res.status = 400;
  return std::nullopt;
}

// The JSON error for a request that no handler answered (or whose body could not be read).
void ReplyUnhandled(const httplib::Request& req, httplib::Response& res, size_t max_body_bytes) {
  if (res.status == 413) {
    ReplyError(res, 413, Str(req.method, " ", req.path, ": body larger than ", max_body_bytes,
                             " bytes; send {\"name\": \"SESSION\"}"));
    res.set_header("Connection", "close");
    return;
  }
  if (const char* allowed = AllowedMethods(req.path); allowed && !MethodAllowed(req.path, req.method)) {
    ReplyError(res, 405, Str(req.method, " ", req.path, ": method not allowed; use ", allowed));
    res.set_header("Allow", allowed);
    return;
  }
  if (!AllowedMethods(req.path) && !req.path.empty()) {
    ReplyError(res, 404, Str(req.method, " ", req.path, ": no such endpoint (GET /status, POST /start, POST /stop, GET / for the live page)"));
    return;
  }
  ReplyError(res, res.status, Str(req.method, " ", req.path, ": malformed request"));
}

// A browser's request from a page of another origin (a script on some web site the operator has open)
// carries that Origin: refused, so that it cannot start or stop sessions through the operator's browser.
AccessDecision CheckOrigin(const httplib::Request& req) {
  const std::string origin = req.get_header_value("Origin");
  if (origin.empty() || origin == "http://" + req.get_header_value("Host")) return {};
  return {403, "control API: requests from pages of " + origin + " are refused (only the daemon's own page)"};
}

// The token as "Bearer T": the header of API clients, else the cookie a browser got from /?token=T,
// else that query itself (on the page only).
std::string Authorization(const httplib::Request& req) {
  if (req.has_header("Authorization")) return req.get_header_value("Authorization");
  const std::string cookies = req.get_header_value("Cookie");
  const std::string key = std::string(kTokenCookie) + "=";
  for (size_t at = 0; at < cookies.size();) {
    const size_t end = std::min(cookies.find(';', at), cookies.size());
    std::string pair = cookies.substr(at, end - at);
    pair.erase(0, pair.find_first_not_of(' '));
    if (pair.rfind(key, 0) == 0) return "Bearer " + pair.substr(key.size());
    at = end + 1;
  }
  if (req.path == "/" && req.has_param("token")) return "Bearer " + req.get_param_value("token");
  return "";
}

// Sent to this daemon only, never to scripts, never along with requests from other sites.
std::string TokenCookie(const std::string& token) {
  return std::string(kTokenCookie) + "=" + token + "; Path=/; HttpOnly; SameSite=Strict";
}

}  // namespace

void ControlServer::AddRoutes() {
  server_->new_task_queue = [threads = options_.worker_threads + options_.max_live_viewers] {
    return new httplib::ThreadPool(static_cast<size_t>(threads));
  };
  server_->set_socket_options([this](socket_t sock) {
    httplib::default_socket_options(sock);  // what httplib sets when no hook is given (address reuse)
    listen_fd_ = static_cast<int>(sock);
  });
  server_->set_keep_alive_timeout(options_.idle_timeout_s);
  server_->set_read_timeout(options_.read_timeout_s);
  server_->set_write_timeout(options_.read_timeout_s);  // a client that does not read its answer
  server_->set_payload_max_length(options_.max_body_bytes);
  server_->set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    AccessDecision access = CheckOrigin(req);
    if (access.status == 0) access = CheckAccess(options_, req.remote_addr, Authorization(req));
    if (access.status == 0) {
      if (req.path == "/" && !options_.token.empty() && req.get_param_value("token") == options_.token)
        res.set_header("Set-Cookie", TokenCookie(options_.token));
      return httplib::Server::HandlerResponse::Unhandled;
    }
    ReplyError(res, access.status, access.error);
    return httplib::Server::HandlerResponse::Handled;
  });
  AddLiveRoutes(*server_, daemon_, *feed_, options_.max_live_viewers);
  server_->Get("/status", [this](const httplib::Request&, httplib::Response& res) {
    Guarded(res, [&] { return daemon_.Status(); });
  });
  // Every request with a body (any path) is read here, bounded; then /start and /stop are served and
  // anything else falls through to the error handler below (405 or 404).
  const auto with_body = [this](const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader) {
    const std::optional<std::string> body = ReadBoundedBody(reader, options_.max_body_bytes, res);
    if (!body) return;  // res.status 413 or 400: the error handler answers
    if (req.method == "POST" && req.path == "/start")
      Guarded(res, [&] { return daemon_.StartSession(SessionNameFromBody(*body, options_.max_json_depth)); });
    else if (req.method == "POST" && req.path == "/stop")
      Guarded(res, [&] { return daemon_.StopSession(); });
    else
      res.status = 404;  // the error handler makes it 405 on a known path
  };
  server_->Post(".*", with_body);
  server_->Put(".*", with_body);
  server_->Patch(".*", with_body);
  server_->Delete(".*", with_body);
  // Wrong methods and unknown paths reach no handler (or with_body's 404): cpp-httplib answers 404 (or
  // 400 for a method it has no handler table for, like TRACE) and this handler turns that into 405 or
  // 404 with a JSON error.
  server_->set_error_handler([this](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;  // already an error of ours
    ReplyUnhandled(req, res, options_.max_body_bytes);
  });
}

}  // namespace mocap::capture
