// mocaplabel capture daemon|start|stop|status: the capture daemon and its control over the local HTTP +
// JSON API (docs/capture.md). The rig file's `capture:` section is read by the pipeline's rig reader
// (pipeline/rig.h) and mapped onto the daemon's options there.
#include <CLI/CLI.hpp>
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>

#include "capture/daemon/control_server.h"
#include "capture/daemon/control_token.h"
#include "capture/daemon/daemon.h"
#include "capture/daemon/daemon_address.h"
#include "capture/daemon/rerecord.h"
#include "capture/daemon/sources.h"
#include "cli/cmd_capture_labeller.h"
#include "cli/parse_args.h"
#include "cli/commands.h"
#include "core/check.h"
#include "pipeline/object_library.h"
#include "pipeline/rig.h"
// Last: it pulls in <resolv.h>, whose `_res` macro breaks Eigen headers included after it.
#include <httplib.h>

namespace mocap::cli {
namespace {

namespace fs = std::filesystem;
using capture::ControlServerOptions;

using CaptureRig = pipeline::CaptureOptions;

CaptureRig LoadCaptureRig(const fs::path& file) { return pipeline::CaptureOptionsOf(pipeline::ReadRig(file)); }

void WaitForSignal(const sigset_t& signals) {
  int signal = 0;
  while (::sigwait(&signals, &signal) != 0) {
  }
  std::fprintf(stderr, "capture: %s received, finishing\n", ::strsignal(signal));
}

// <sessions_dir>/.capture-daemon.json while the daemon listens: clients given only the rig find its port.
class AddressFileGuard {
 public:
  AddressFileGuard(fs::path sessions_dir, const capture::DaemonAddress& address)
      : sessions_dir_(std::move(sessions_dir)), pid_(address.pid) {
    capture::WriteDaemonAddress(sessions_dir_, address);
  }
  ~AddressFileGuard() { capture::RemoveDaemonAddress(sessions_dir_, pid_); }
  AddressFileGuard(const AddressFileGuard&) = delete;
  AddressFileGuard& operator=(const AddressFileGuard&) = delete;

 private:
  fs::path sessions_dir_;
  int64_t pid_;
};

// The live page's thumbnails, and their labels when an object library is given (docs/live-page.md).
struct LiveFlags {
  std::string objects;
  double thumbnail_hz = capture::LiveViewOptions{}.thumbnail_rate_hz;
};

void ApplyLiveFlags(const LiveFlags& flags, const pipeline::Rig& rig, capture::CaptureDaemonOptions& daemon) {
  daemon.live.thumbnail_rate_hz = flags.thumbnail_hz;
  if (flags.objects.empty()) return;
  // One rendering thread at a low rate: llvmpipe's own rasteriser threads would only compete with the
  // recording for the cores. Mesa reads this once, at the first EGL display, which is still to come.
  if (std::getenv("LP_NUM_THREADS") == nullptr) setenv("LP_NUM_THREADS", "0", 0);
  daemon.labeller = std::make_shared<RigFrameLabeller>(
      pipeline::LabelRigOf(rig), pipeline::LabelObjectsOf(pipeline::ReadObjectLibrary(flags.objects)));
}

int RunDaemon(const fs::path& rig_path, const std::optional<fs::path>& sessions, ControlServerOptions overrides,
              bool port_given, bool bind_given, bool json, const LiveFlags& live) {
  const pipeline::Rig full_rig = pipeline::ReadRig(rig_path);
  CaptureRig rig = pipeline::CaptureOptionsOf(full_rig);
  ApplyLiveFlags(live, full_rig, rig.daemon);
  if (sessions) rig.daemon.sessions_dir = *sessions;
  if (port_given) rig.control.port = overrides.port;
  if (bind_given) rig.control.bind = overrides.bind;
  rig.control.allow_remote = overrides.allow_remote;
  rig.control.token = overrides.token;
  rig.control.check();
  fs::create_directories(rig.daemon.sessions_dir);

  sigset_t signals;  // blocked in every thread; the main thread waits for them
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  ::pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  std::vector<std::unique_ptr<capture::CaptureSource>> sources;
  if (rig.tracker) sources.push_back(capture::CreateNdiSource(*rig.tracker));
  for (const capture::CameraSourceOptions& camera : rig.cameras) sources.push_back(capture::CreateCameraSource(camera));
  capture::CaptureDaemon daemon(rig.daemon, std::move(sources));
  capture::ControlServer server(daemon, rig.control);
  const AddressFileGuard address_file(rig.daemon.sessions_dir, {rig.control.bind, server.port(), ::getpid()});
  const nlohmann::json where = {{"bind", rig.control.bind}, {"port", server.port()},
                                {"sessions_dir", rig.daemon.sessions_dir.string()}, {"pid", ::getpid()}};
  if (json) std::printf("%s\n", where.dump().c_str());
  else std::printf("capture daemon on http://%s:%d (live page: open it in a browser), sessions in %s (SIGTERM or Ctrl-C to stop)\n",
                   rig.control.bind.c_str(), server.port(), rig.daemon.sessions_dir.c_str());
  std::fflush(stdout);

  WaitForSignal(signals);
  server.Stop();
  try {
    const nlohmann::json summary = daemon.StopSession();
    std::fprintf(stderr, "capture: session finished: %s\n", summary.dump().c_str());
  } catch (const capture::StateError&) {
  }
  return 0;
}

struct ClientFlags {
  std::string host = "127.0.0.1";
  int port = 8780;
  std::string token;
  std::string token_file;
  std::string rig;
  std::string sessions;  ///< the daemon's --sessions, where it wrote its address
  bool json = false;
};

// --rig R: the address the running daemon wrote into its sessions folder, else R's control section
// (where port 0 means "any free port": only the daemon's file can tell which).
ClientFlags DaemonAddressOf(const ClientFlags& flags) {
  ClientFlags where = flags;
  const CaptureRig rig = LoadCaptureRig(flags.rig);
  const fs::path sessions = flags.sessions.empty() ? rig.daemon.sessions_dir : fs::path(flags.sessions);
  const std::optional<capture::DaemonAddress> running = capture::ReadDaemonAddress(sessions);
  const std::string bind = running ? running->bind : rig.control.bind;
  where.port = running ? running->port : rig.control.port;
  if (bind != "0.0.0.0") where.host = bind;
  if (where.port == 0)
    throw InputError(flags.rig, Str("control.port is 0 and no running daemon wrote its port to ",
                                    capture::DaemonAddressFile(sessions).string(),
                                    ": start `mocaplabel capture daemon --rig ", flags.rig, "` (with the same --sessions) or give --port"));
  return where;
}

// One request to the daemon; prints the answer and returns the exit status.
int Request(const ClientFlags& flags, const std::string& method, const std::string& path, const nlohmann::json& body,
            const std::function<void(const nlohmann::json&)>& print) {
  const ClientFlags where = flags.rig.empty() ? flags : DaemonAddressOf(flags);
  httplib::Client client(where.host, where.port);
  client.set_connection_timeout(2);
  client.set_read_timeout(30);
  httplib::Headers headers;
  const std::string token = capture::ResolveControlToken(capture::TokenSourcesFromEnvironment(flags.token, flags.token_file));
  if (!token.empty()) headers.emplace("Authorization", "Bearer " + token);
  const httplib::Result result = method == "GET" ? client.Get(path, headers)
                                                 : client.Post(path, headers, body.dump(), "application/json");
  if (!result)
    throw InputError(Str("capture daemon at ", where.host, ":", where.port),
                     Str("cannot be reached (", httplib::to_string(result.error()), "): is `mocaplabel capture daemon` running?"));
  nlohmann::json answer = nlohmann::json::parse(result->body, nullptr, false);
  if (answer.is_discarded()) answer = {{"error", "the daemon answered something that is not JSON: " + result->body}};
  if (flags.json) std::printf("%s\n", answer.dump().c_str());
  if (result->status != 200) {
    std::fprintf(stderr, "mocaplabel capture: %s\n", answer.value("error", std::string("request failed")).c_str());
    return 1;
  }
  if (!flags.json) print(answer);
  if (answer.contains("error") && answer["error"].is_string() && !answer["error"].get<std::string>().empty()) {
    std::fprintf(stderr, "mocaplabel capture: session failed: %s\n", answer["error"].get<std::string>().c_str());
    return 1;
  }
  return 0;
}

void PrintStatus(const nlohmann::json& s) {
  std::printf("state: %s\n", s["state"].get<std::string>().c_str());
  if (s["session"].is_object()) std::printf("session: %s\n", s["session"].dump().c_str());
  for (const auto& source : s["sources"]) std::printf("source %s: %s %s\n", source["name"].get<std::string>().c_str(),
                                                      source["state"].get<std::string>().c_str(), source["device"].dump().c_str());
  for (const auto& [name, stream] : s["streams"].items())
    std::printf("stream %s: %.1f Hz, %lld received, bodies %s\n", name.c_str(), stream["rate_hz"].get<double>(),
                stream["received"].get<long long>(), stream["bodies"].dump().c_str());
  if (s.contains("queues")) std::printf("queues: %s\n", s["queues"].dump().c_str());
  std::printf("disk: %s\n", s["disk"].dump().c_str());
}

int PrintReplay(const capture::RerecordResult& r, bool json) {
  const nlohmann::json result = {{"complete", r.complete}, {"source_frames", r.source_frames},
                                 {"recorded_frames", r.recorded_frames}, {"dropped_frames", r.dropped_frames},
                                 {"tracker_rate_hz", r.tracker_rate_hz}, {"poll_rate_hz", r.poll_rate_hz},
                                 {"camera", r.camera}, {"tracker", r.tracker}, {"summary", r.summary}, {"seconds", r.seconds}};
  if (json) std::printf("%s\n", result.dump().c_str());
  else std::printf("replayed %lld of %lld frames (%lld late, at most %.1f ms), tracker %.1f Hz polled at %.0f Hz: %s\n",
                   static_cast<long long>(r.recorded_frames), static_cast<long long>(r.source_frames),
                   r.camera.value("late_frames", 0LL), r.camera.value("max_late_ms", 0.0), r.tracker_rate_hz, r.poll_rate_hz,
                   r.complete ? "complete" : "INCOMPLETE");
  return r.complete ? 0 : 1;
}

void AddClientFlags(CLI::App* command, ClientFlags& flags) {
  command->add_option("--host", flags.host, "daemon address")->capture_default_str();
  command->add_option("--port", flags.port, "daemon control port")->capture_default_str();
  command->add_option("--token", flags.token, "token the daemon was started with (visible in ps: prefer --token-file or $MOCAPLABEL_TOKEN)");
  command->add_option("--token-file", flags.token_file, "read the token from the first line of this file");
  command->add_option("--rig", flags.rig, "find the daemon started with this rig file (its sessions folder, then its control section)");
  command->add_option("--sessions", flags.sessions, "with --rig: the daemon's --sessions folder, if it was given one");
  command->add_flag("--json", flags.json, "print the daemon's JSON answer on stdout");
}

}  // namespace

int RunCapture(int argc, char** argv) {
  CLI::App app{"The capture daemon and its control (docs/capture.md)", "mocaplabel capture"};
  app.require_subcommand(1);
  CLI::App* daemon = app.add_subcommand("daemon", "connect the rig's devices, keep them streaming, serve the control API");
  std::string rig_path, sessions;
  ControlServerOptions control;
  bool daemon_json = false;
  daemon->add_option("--rig", rig_path, "rig file with a capture: section")->required();
  daemon->add_option("--sessions", sessions, "folder for sessions (overrides the rig's sessions_dir)");
  CLI::Option* port = daemon->add_option("--port", control.port, "control port (0: any free port)");
  CLI::Option* bind = daemon->add_option("--bind", control.bind, "control address (non-loopback needs --allow-remote)");
  daemon->add_flag("--allow-remote", control.allow_remote, "serve clients that are not on loopback (needs --token)");
  std::string token_file;
  daemon->add_option("--token", control.token,
                     "require 'Authorization: Bearer TOKEN' from every client (visible in ps: prefer --token-file or $MOCAPLABEL_TOKEN)");
  daemon->add_option("--token-file", token_file, "read the token from the first line of this file");
  daemon->add_flag("--json", daemon_json, "print where it listens as one JSON line on stdout");
  LiveFlags live;
  daemon->add_option("--objects", live.objects, "object library: draw the objects' labels on the live page's thumbnails");
  daemon->add_option("--thumbnail-hz", live.thumbnail_hz, "live page thumbnails per second per camera (0: none)")
      ->capture_default_str()->check(CLI::Range(0.0, 30.0));

  ClientFlags flags;
  std::string name;
  CLI::App* start = app.add_subcommand("start", "start recording a session");
  start->add_option("--name", name, "session name (folder under the sessions folder)")->required();
  CLI::App* stop = app.add_subcommand("stop", "stop the session and close it");
  CLI::App* status = app.add_subcommand("status", "rates, drops, queues, disk, visible bodies");
  for (CLI::App* command : {start, stop, status}) AddClientFlags(command, flags);
  CLI::App* replay = app.add_subcommand("replay", "re-record a session through the daemon in real time (NDI emulator + camera replay)");
  capture::RerecordOptions rerecord;
  std::string replay_source, replay_out;
  bool replay_json = false;
  replay->add_option("source", replay_source, "session to replay (one camera, one tracker)")->required();
  replay->add_option("--out", replay_out, "new session folder (must not exist)")->required();
  replay->add_option("--poll-factor", rerecord.poll_factor, "BX polls per tracker frame")->capture_default_str();
  replay->add_flag("--json", replay_json, "print the result as JSON");
  MOCAP_PARSE(app, argc, argv);

  if (replay->parsed()) {
    rerecord.source_session = replay_source;
    rerecord.out_session = replay_out;
    return PrintReplay(capture::RerecordSession(rerecord), replay_json);
  }

  if (daemon->parsed()) {
    control.token = capture::ResolveControlToken(capture::TokenSourcesFromEnvironment(control.token, token_file));
    return RunDaemon(rig_path, sessions.empty() ? std::nullopt : std::optional<fs::path>(sessions), control,
                     port->count() > 0, bind->count() > 0, daemon_json, live);
  }
  if (start->parsed())
    return Request(flags, "POST", "/start", {{"name", name}},
                   [](const nlohmann::json& a) { std::printf("recording %s\n", a["dir"].get<std::string>().c_str()); });
  if (stop->parsed())
    return Request(flags, "POST", "/stop", nlohmann::json::object(),
                   [](const nlohmann::json& a) { std::printf("stopped: %s\n", a.dump().c_str()); });
  return Request(flags, "GET", "/status", nullptr, PrintStatus);
}

}  // namespace mocap::cli
