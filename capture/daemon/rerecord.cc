#include "capture/daemon/rerecord.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "capture/daemon/daemon.h"
#include "capture/daemon/session_replay.h"
#include "capture/daemon/sources.h"
#include "capture/ndi/emulator.h"
#include "core/check.h"

namespace mocap::capture {
namespace {

namespace fs = std::filesystem;

// The tracker's frame rate from the median spacing of each body's consecutive stamps.
double RecordedRateHz(const std::vector<ndi::RecordedBody>& bodies) {
  std::vector<int64_t> steps;
  for (const ndi::RecordedBody& body : bodies)
    for (size_t k = 1; k < body.samples.size(); ++k)
      if (body.samples[k].stamp_ns > body.samples[k - 1].stamp_ns)
        steps.push_back(body.samples[k].stamp_ns - body.samples[k - 1].stamp_ns);
  if (steps.empty()) throw InputError("re-record", "the tracker stream has too few samples to tell its rate");
  std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
  return 1e9 / static_cast<double>(steps[steps.size() / 2]);
}

void SleepUntil(int64_t host_ns) {
  const int64_t wait_ns = host_ns - MonotonicNowNs();
  if (wait_ns > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait_ns));
}

const nlohmann::json& SourceStatus(const nlohmann::json& status, const std::string& name) {
  for (const nlohmann::json& source : status.at("sources"))
    if (source.at("name") == name) return source.at("device");
  throw InputError("re-record", "the daemon lists no source '" + name + "'");
}

// The daemon's status once the camera replay has handed over its last record (or at `deadline_ns`).
nlohmann::json WaitForReplay(const CaptureDaemon& daemon, const std::string& camera, int64_t deadline_ns) {
  for (;;) {
    nlohmann::json status = daemon.Status();
    if (SourceStatus(status, camera).value("finished", false) || MonotonicNowNs() >= deadline_ns) return status;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

int64_t LastStampNs(const SessionReader& source, const std::string& camera, const ndi::RecordedTrajectory& trajectory) {
  const int64_t frames = source.frame_count(camera);
  const int64_t last_frame = frames > 0 ? source.frame(camera, frames - 1).record.stamp_ns : 0;
  return std::max(last_frame, trajectory.last_stamp_ns());
}

}  // namespace

void RerecordOptions::check() const {
  if (source_session.empty() || out_session.empty()) throw InputError("re-record", "needs a source and an output session");
  if (fs::exists(out_session)) throw InputError(out_session.string(), "exists already: choose another output session");
  if (tracker_rate_hz < 0) throw InputError("re-record", "tracker_rate_hz must be >= 0 (0: the recording's)");
  if (!(poll_factor >= 1 && poll_factor <= 50)) throw InputError("re-record", "poll_factor must be in [1, 50]");
  if (!(lead_in_s >= 0.1 && lead_in_s <= 30)) throw InputError("re-record", "lead_in_s must be in [0.1, 30]");
  if (!(tail_s >= 0 && tail_s <= 30)) throw InputError("re-record", "tail_s must be in [0, 30]");
  if (!(max_overrun_s >= 0)) throw InputError("re-record", "max_overrun_s must be >= 0");
}

RerecordResult RerecordSession(const RerecordOptions& options) {
  options.check();
  const auto started = std::chrono::steady_clock::now();
  const SessionReader source = SessionReader::Open(options.source_session);
  const std::string camera = OnlyCamera(source.manifest()), tracker = OnlyTracker(source.manifest());
  if (camera.empty() || tracker.empty())
    throw InputError(options.source_session.string(), "re-recording needs a camera and a tracker stream");
  RerecordResult result;
  result.source_frames = source.frame_count(camera);
  const int64_t origin_ns = FirstStampNs(source);
  const int64_t lead_ns = std::llround(options.lead_in_s * 1e9);

  std::vector<ndi::RecordedBody> bodies = RecordedBodies(source, tracker);
  result.tracker_rate_hz = options.tracker_rate_hz > 0 ? options.tracker_rate_hz : RecordedRateHz(bodies);
  result.poll_rate_hz = result.tracker_rate_hz * options.poll_factor;
  std::vector<ndi::ToolSpec> tools;
  for (const ndi::RecordedBody& body : bodies) tools.push_back({body.name});
  ndi::RecordedTrajectoryOptions trajectory_options;
  trajectory_options.origin_ns = origin_ns - lead_ns;  // tracking time lead_in_s is the recording's origin
  auto trajectory = std::make_shared<ndi::RecordedTrajectory>(std::move(bodies), trajectory_options);

  ndi::EmulatorOptions emulator_options;
  emulator_options.port = 0;
  emulator_options.tracker.rate_hz = result.tracker_rate_hz;
  ndi::Emulator emulator(emulator_options, trajectory);
  emulator.Start();
  const int64_t start_host_ns = emulator.start_ns() + lead_ns;

  NdiSourceOptions ndi_options;
  ndi_options.stream = tracker;
  ndi_options.model = source.manifest().FindTracker(tracker)->model;
  ndi_options.client.port = emulator.port();
  ndi_options.client.poll_rate_hz = result.poll_rate_hz;
  ndi_options.client.tools = tools;
  SessionCameraReplayOptions camera_options;
  camera_options.session_dir = options.source_session;
  camera_options.camera = camera;
  camera_options.origin_ns = origin_ns;
  camera_options.start_host_ns = start_host_ns;
  std::vector<std::unique_ptr<CaptureSource>> sources;
  sources.push_back(CreateSessionCameraReplay(camera_options, source));  // a copy: `source` is read below
  sources.push_back(CreateNdiSource(ndi_options));

  CaptureDaemonOptions daemon_options;
  daemon_options.sessions_dir = options.out_session.parent_path().empty() ? "." : options.out_session.parent_path();
  daemon_options.rig_name = "re-recorded " + source.manifest().source;
  daemon_options.manifest_extra = {{"rerecorded_from", fs::absolute(options.source_session).string()},
                                   {"source_extra", source.manifest().extra},
                                   {"tracker_poll_rate_hz", result.poll_rate_hz}};
  daemon_options.recorder = options.recorder;
  auto daemon = std::make_unique<CaptureDaemon>(daemon_options, std::move(sources));
  daemon->StartSession(options.out_session.filename().string());
  const int64_t end_ns = start_host_ns + (LastStampNs(source, camera, *trajectory) - origin_ns) + std::llround(options.tail_s * 1e9);
  SleepUntil(end_ns);
  const nlohmann::json status = WaitForReplay(*daemon, camera, end_ns + std::llround(options.max_overrun_s * 1e9));
  result.camera = SourceStatus(status, camera);
  result.tracker = SourceStatus(status, tracker);
  result.summary = daemon->StopSession();
  daemon.reset();  // closes the NDI link before the emulator goes (else the client reports a lost tracker)
  emulator.Stop();

  result.recorded_frames = result.summary.at("streams").value(camera, nlohmann::json::object()).value("written", int64_t{0});
  result.dropped_frames = result.source_frames - result.recorded_frames;
  result.complete = result.summary.value("complete", false) && result.dropped_frames == 0;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace mocap::capture
