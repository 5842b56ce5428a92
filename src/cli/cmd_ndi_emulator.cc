// mocaplabel ndi-emulator: an NDI Combined API tracker on loopback (or a pseudo-terminal) serving
// scripted rigid bodies with noise, dropouts, latency and corrupted bytes (docs/ndi.md).
#include <CLI/CLI.hpp>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <mutex>
#include <optional>
#include <nlohmann/json.hpp>

#include "capture/daemon/session_replay.h"
#include "capture/ndi/emulator.h"
#include "capture/ndi/recorded_trajectory.h"
#include "capture/ndi/trajectory.h"
#include "cli/parse_args.h"
#include "cli/commands.h"
#include "core/check.h"

namespace mocap::cli {
namespace {

// Blocks until SIGINT/SIGTERM or `duration_s` (0: no limit). The signals are blocked in every thread.
void WaitForStop(const sigset_t& signals, double duration_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(duration_s);
  while (duration_s <= 0 || std::chrono::steady_clock::now() < deadline) {
    timespec tick{0, 100'000'000};
    if (::sigtimedwait(&signals, nullptr, &tick) > 0) return;
  }
}

// A pseudo-terminal whose slave end a serial client opens; returns the master fd.
int OpenPty(std::string& slave_path) {
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || ::grantpt(master) != 0 || ::unlockpt(master) != 0) throw InputError("--pty", "cannot create a pseudo-terminal");
  slave_path = ::ptsname(master);
  return master;
}

// The --truth CSV: one row per body per served reply, in the tracker's units converted to metres.
class TruthWriter {
 public:
  explicit TruthWriter(const std::string& path) : file_(std::fopen(path.c_str(), "w")) {
    if (!file_) throw InputError(path, "cannot write the ground-truth file");
    std::fprintf(file_, "frame,handle,status,x_m,y_m,z_m,qw,qx,qy,qz,port_status,corrupted\n");
  }
  ~TruthWriter() { std::fclose(file_); }
  void Write(const ndi::TrackingReply& reply, bool corrupted) {
    std::lock_guard lock(mutex_);
    for (const ndi::HandleReport& h : reply.handles) {
      std::fprintf(file_, "%u,%d,%s,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%u,%d\n", h.frame_number, h.handle,
                   std::string(ndi::ToString(h.status)).c_str(), h.t_mm[0] * 1e-3, h.t_mm[1] * 1e-3, h.t_mm[2] * 1e-3,
                   h.q_wxyz[0], h.q_wxyz[1], h.q_wxyz[2], h.q_wxyz[3], h.port_status, corrupted ? 1 : 0);
    }
    std::fflush(file_);
  }

 private:
  std::FILE* file_;
  std::mutex mutex_;
};

// Recording time of tracking time 0: the first camera frame, so that a replay of the same session's
// camera started with tracking (fakenect at `capture start`) lines up; without a camera the first stamp.
int64_t ReplayOriginNs(const SessionReader& session) {
  std::optional<int64_t> first_frame_ns;
  for (const CameraStreamInfo& camera : session.manifest().cameras)
    if (session.frame_count(camera.name) > 0)
      first_frame_ns = std::min(first_frame_ns.value_or(INT64_MAX), session.frame(camera.name, 0).record.stamp_ns);
  return first_frame_ns.value_or(capture::FirstStampNs(session));
}

// A session's tracker stream, played from tracking time 0 (the client's TSTART).
std::shared_ptr<const ndi::TrajectorySource> ReplayTrajectory(const std::string& session_dir, const std::string& tracker) {
  const SessionReader session = SessionReader::Open(session_dir);
  ndi::RecordedTrajectoryOptions options;
  options.origin_ns = ReplayOriginNs(session);
  return std::make_shared<ndi::RecordedTrajectory>(capture::RecordedBodies(session, tracker), options);
}

}  // namespace

int RunNdiEmulator(int argc, char** argv) {
  CLI::App app{"Emulate an NDI tracker (Combined API over TCP or a pseudo-terminal)", "mocaplabel ndi-emulator"};
  ndi::EmulatorOptions options;
  int bodies = 2;
  std::string script_path, truth_path, replay_path, replay_tracker;
  double duration_s = 0;
  bool passive = false, pty = false, json = false;
  app.add_option("--port", options.port, "TCP port (0: any free port)")->capture_default_str();
  app.add_option("--bind", options.bind, "listen address (IPv4)")->capture_default_str();
  app.add_option("--bodies", bodies, "bodies on circles when no --script is given")->capture_default_str();
  app.add_option("--rate", options.tracker.rate_hz, "frame rate, Hz")->capture_default_str();
  app.add_option("--noise-mm", options.tracker.noise_mm, "position noise sigma per axis, mm")->capture_default_str();
  app.add_option("--dropout", options.tracker.dropout, "probability a body is MISSING in a frame")->capture_default_str();
  app.add_option("--latency-ms", options.latency_ms, "delay before each BX/TX reply, ms")->capture_default_str();
  app.add_option("--corrupt", options.corrupt, "probability a BX/TX reply gets one byte flipped")->capture_default_str();
  app.add_option("--seed", options.tracker.seed, "seed of noise, dropouts and corruption")->capture_default_str();
  CLI::Option* script_option = app.add_option("--script", script_path, "trajectory script (docs/ndi.md)");
  app.add_option("--replay", replay_path, "serve a recorded session's tracker stream instead (e.g. from `sim record`)")
      ->excludes(script_option);
  app.add_option("--replay-tracker", replay_tracker, "tracker stream of --replay (default: the session's only one)");
  app.add_flag("--passive", passive, "no preloaded handles: tools must be requested with PHRQ and uploaded with PVWR");
  app.add_flag("--pty", pty, "serve on a pseudo-terminal (serial path) instead of TCP; prints its path");
  app.add_option("--truth", truth_path, "write every served BX/TX body to this CSV (ground truth)");
  app.add_option("--duration", duration_s, "stop after this many seconds (0: at SIGINT/SIGTERM)");
  app.add_flag("--json", json, "print one JSON document (where it listens) on stdout");
  MOCAP_PARSE(app, argc, argv);

  if (duration_s < 0) throw InputError("--duration", "must not be negative");
  if (bodies < 1 || bodies > 200) throw InputError("--bodies", Str(bodies, " is not in [1, 200]"));
  options.tracker.preloaded_handles = !passive;
  options.tracker.clock_from_tstart = true;  // a client connecting late still hears frame 1000 and t = 0 first
  options.log_replay_end = true;
  std::shared_ptr<const ndi::TrajectorySource> trajectory;
  if (!replay_path.empty()) {
    trajectory = ReplayTrajectory(replay_path, replay_tracker);
  } else {
    ndi::TrajectoryScript script = script_path.empty() ? ndi::DefaultTrajectoryScript(bodies)
                                                       : ndi::LoadTrajectoryScript(script_path);
    options.tracker.volume = script.volume;
    trajectory = std::make_shared<ndi::ScriptedTrajectory>(script);
  }

  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  ::pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  ndi::Emulator emulator(options, trajectory);
  std::unique_ptr<TruthWriter> truth;
  if (!truth_path.empty()) {
    truth = std::make_unique<TruthWriter>(truth_path);
    emulator.SetServedCallback([&truth](const ndi::TrackingReply& reply, bool corrupted) { truth->Write(reply, corrupted); });
  }
  std::string pty_path;
  int master = -1;
  if (pty) {
    master = OpenPty(pty_path);
    emulator.ServeFd(master);
  } else {
    emulator.Start();
  }
  nlohmann::json names = nlohmann::json::array();
  for (int i = 0; i < trajectory->body_count(); ++i) names.push_back(trajectory->body_name(i));
  nlohmann::json where = pty ? nlohmann::json{{"pty", pty_path}}
                             : nlohmann::json{{"bind", options.bind}, {"port", emulator.port()}};
  where["bodies"] = names;
  where["rate_hz"] = options.tracker.rate_hz;
  if (json) std::printf("%s\n", where.dump().c_str());
  else std::printf("NDI emulator on %s, %zu bodies at %g Hz (Ctrl-C to stop)\n",
                   pty ? pty_path.c_str() : (options.bind + ":" + std::to_string(emulator.port())).c_str(),
                   names.size(), options.tracker.rate_hz);
  std::fflush(stdout);

  WaitForStop(signals, duration_s);
  emulator.Stop();
  if (master >= 0) ::close(master);
  const ndi::EmulatorStats stats = emulator.stats();
  std::fprintf(stderr, "ndi-emulator: %llu connections, %llu commands, %llu tracking replies, %llu corrupted, %llu errors, "
               "%llu past the replay's end\n",
               static_cast<unsigned long long>(stats.connections), static_cast<unsigned long long>(stats.commands),
               static_cast<unsigned long long>(stats.tracking_replies),
               static_cast<unsigned long long>(stats.corrupted_replies), static_cast<unsigned long long>(stats.error_replies),
               static_cast<unsigned long long>(stats.past_end_replies));
  return 0;
}

}  // namespace mocap::cli
