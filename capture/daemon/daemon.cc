#include "capture/daemon/daemon.h"

#include <sys/statvfs.h>

#include <deque>

#include "capture/daemon/software_version.h"
#include "core/check.h"
#include "core/log.h"

namespace mocap::capture {

namespace fs = std::filesystem;

void CaptureDaemonOptions::check() const {
  if (sessions_dir.empty()) throw InputError("sessions_dir", "is empty: say where sessions go");
  if (!manifest_extra.is_object()) throw InputError("manifest_extra", "must be a JSON object");
  RecorderOptions r = recorder;
  r.session_dir = sessions_dir / "x";
  r.check();
  live.check();
}

void CheckSessionName(const std::string& name) {
  if (name.empty() || name.size() > 128) throw InputError("session name", "must be 1..128 characters");
  if (name[0] == '.') throw InputError("session name '" + name + "'", "must not start with '.'");
  for (const char c : name) {
    const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-';
    if (!ok) throw InputError("session name '" + name + "'", "may only hold letters, digits, '.', '_' and '-'");
  }
}

// Live figures of one stream, kept whether or not a session records.
struct CaptureDaemon::StreamStats {
  int64_t received = 0;
  int64_t last_stamp_ns = 0;
  std::deque<int64_t> recent_ns;  ///< receive times within the last second (frames or tracker frames)
  struct Body {
    PoseStatus status = PoseStatus::kMissing;
    int64_t stamp_ns = 0;
    int markers = -1;  ///< as the tracker last measured them; -1 when it does not say
  };
  std::map<std::string, Body> bodies;

  void Note(int64_t stamp_ns, bool new_instant) {
    ++received;
    if (new_instant) recent_ns.push_back(stamp_ns);
    last_stamp_ns = stamp_ns;
    while (!recent_ns.empty() && recent_ns.front() < stamp_ns - 1'000'000'000) recent_ns.pop_front();
  }
};

CaptureDaemon::CaptureDaemon(const CaptureDaemonOptions& options, std::vector<std::unique_ptr<CaptureSource>> sources)
    : options_(options), sources_(std::move(sources)) {
  options_.check();
  live_ = std::make_unique<LiveView>(options_.live, options_.labeller, [this] { return BuildManifest(); });
  try {
    for (auto& source : sources_) {
      source->Open();
      if (!source->starts_with_session()) source->Start(this);
    }
  } catch (...) {
    for (auto& source : sources_) source->Close();  // before the members they push into are gone
    live_.reset();  // its thread reads the sources' stream entries
    throw;
  }
  watcher_ = std::thread([this] { WatchForFailure(); });
}

CaptureDaemon::~CaptureDaemon() {
  stop_ = true;
  if (watcher_.joinable()) watcher_.join();
  for (auto& source : sources_) source->Close();  // no producer left when the recorder stops
  live_.reset();  // before the sources whose stream entries its thread reads
  std::shared_ptr<Recorder> recorder;
  {
    std::lock_guard lock(session_mutex_);
    recorder = std::move(recorder_);
  }
  if (recorder) recorder->Stop();
}

CaptureDaemon::StreamStats& CaptureDaemon::stats(const std::string& stream) {
  auto& slot = stats_[stream];
  if (!slot) slot = std::make_unique<StreamStats>();
  return *slot;
}

void CaptureDaemon::PushFrame(CapturedFrame&& frame) {
  {
    std::lock_guard lock(stats_mutex_);
    stats(frame.camera).Note(MonotonicNowNs(), true);
  }
  live_->OnFrame(frame);
  std::shared_ptr<Recorder> recorder;
  {
    std::lock_guard lock(session_mutex_);
    recorder = recorder_;
  }
  if (recorder) recorder->PushFrame(std::move(frame));
}

void CaptureDaemon::PushSample(CapturedSample&& sample) {
  {
    std::lock_guard lock(stats_mutex_);
    StreamStats& s = stats(sample.tracker);
    s.Note(sample.record.stamp_ns, sample.record.stamp_ns != s.last_stamp_ns);
    s.bodies[sample.record.body] = {sample.record.status, sample.record.stamp_ns, sample.markers};
  }
  live_->OnSample(sample);
  std::shared_ptr<Recorder> recorder;
  {
    std::lock_guard lock(session_mutex_);
    recorder = recorder_;
  }
  if (recorder) recorder->PushSample(std::move(sample));
}

void CaptureDaemon::PushEvent(EventRecord&& event) {
  // Device events (gaps, reconnects, tracker alerts) matter to whoever watches the daemon, too.
  Log().log(event.kind == "error" ? spdlog::level::err : spdlog::level::warn, "capture: {} {}: {}", event.kind,
            event.stream, event.detail);
  live_->OnEvent(event);
  std::shared_ptr<Recorder> recorder;
  {
    std::lock_guard lock(session_mutex_);
    recorder = recorder_;
  }
  if (recorder) recorder->PushEvent(std::move(event));
}

SessionManifest CaptureDaemon::BuildManifest() const {
  SessionManifest manifest;
  manifest.source = "capture";
  manifest.software_version = CaptureSoftwareVersion();
  for (const auto& source : sources_) AddStream(manifest, source->stream_info());
  manifest.extra = options_.manifest_extra;
  manifest.extra["rig"] = options_.rig_name;
  return manifest;
}

nlohmann::json CaptureDaemon::StartSession(const std::string& name) {
  CheckSessionName(name);
  const fs::path dir = options_.sessions_dir / name;
  {
    std::lock_guard lock(session_mutex_);
    if (recorder_) throw StateError("session '" + session_name_ + "' is recording: stop it first");
    if (fs::exists(dir)) throw InputError(dir.string(), "exists already: choose another session name");
    RecorderOptions recorder_options = options_.recorder;
    recorder_options.session_dir = dir;
    recorder_ = Recorder::Start(recorder_options, BuildManifest());
    session_name_ = name;
    failed_summary_.reset();
  }
  Log().info("capture: recording {}", dir.string());
  live_->OnEvent({MonotonicNowNs(), "note", "", "recording session " + name});
  StartReplays();  // without session_mutex_: a starting source pushes its first events at once
  return {{"session", name}, {"dir", dir.string()}, {"state", "recording"}};
}

// A replay that cannot start (its device refuses) is an error event of the session, not a failed start:
// the other sources record on. Replays started by an earlier session play on.
void CaptureDaemon::StartReplays() {
  std::lock_guard lock(replay_mutex_);
  for (auto& source : sources_) {
    if (!source->starts_with_session() || source->state() != DeviceState::kOpen) continue;
    try {
      source->Start(this);
      PushEvent({MonotonicNowNs(), "note", source->name(), "replay started with this session"});
    } catch (const std::exception& e) {
      PushEvent({MonotonicNowNs(), "error", source->name(), std::string("replay did not start: ") + e.what()});
    }
  }
}

nlohmann::json CaptureDaemon::StopSession() {
  std::shared_ptr<Recorder> recorder;
  {
    std::lock_guard lock(session_mutex_);
    if (!recorder_) {
      if (!failed_summary_) throw StateError("no session is recording");
      nlohmann::json summary = failed_summary_->ToJson();
      failed_summary_.reset();
      return summary;
    }
    recorder = std::move(recorder_);
  }
  const RecorderSummary summary = recorder->Stop();
  Log().info("capture: stopped {} ({})", summary.session_dir.string(),
             summary.complete ? std::string("complete") : summary.error);
  live_->OnEvent({MonotonicNowNs(), summary.complete ? "note" : "error", "",
                  "stopped session " + summary.session_dir.filename().string() +
                      (summary.complete ? "" : ": " + summary.error)});
  return summary.ToJson();
}

// A session whose writer failed is stopped here, at once, so the devices' frames stop queueing for it.
void CaptureDaemon::WatchForFailure() {
  while (!stop_) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::shared_ptr<Recorder> recorder;
    {
      std::lock_guard lock(session_mutex_);
      if (!recorder_ || !recorder_->failed()) continue;
      recorder = std::move(recorder_);
    }
    RecorderSummary summary = recorder->Stop();
    std::lock_guard lock(session_mutex_);
    failed_summary_ = std::move(summary);
  }
}

namespace {

nlohmann::json DiskStatus(const fs::path& dir) {
  struct statvfs vfs {};
  if (::statvfs(dir.c_str(), &vfs) != 0) return {{"path", dir.string()}, {"error", "cannot stat the folder"}};
  return {{"path", dir.string()},
          {"free_bytes", static_cast<uint64_t>(vfs.f_bavail) * vfs.f_frsize},
          {"total_bytes", static_cast<uint64_t>(vfs.f_blocks) * vfs.f_frsize}};
}

}  // namespace

nlohmann::json CaptureDaemon::Status() const {
  nlohmann::json status;
  const int64_t now_ns = MonotonicNowNs();
  {
    std::lock_guard lock(session_mutex_);
    if (recorder_) {
      status["state"] = "recording";
      status["session"] = recorder_->Snapshot().ToJson();
      status["session"]["name"] = session_name_;
      status["queues"] = recorder_->QueueStatus();
    } else {
      status["state"] = failed_summary_ ? "failed" : "idle";
      status["session"] = failed_summary_ ? failed_summary_->ToJson() : nlohmann::json(nullptr);
    }
  }
  nlohmann::json sources = nlohmann::json::array();
  for (const auto& source : sources_)
    sources.push_back({{"name", source->name()}, {"state", ToString(source->state())}, {"device", source->device_status()}});
  status["sources"] = sources;
  nlohmann::json streams = nlohmann::json::object();
  std::lock_guard lock(stats_mutex_);
  for (const auto& [name, s] : stats_) {
    nlohmann::json bodies = nlohmann::json::object();
    for (const auto& [body, b] : s->bodies) {
      bodies[body] = {{"status", ToString(b.status)}, {"visible", HasPose(b.status) && now_ns - b.stamp_ns < 500'000'000}};
      if (b.markers >= 0) bodies[body]["markers"] = b.markers;
    }
    const size_t recent = s->recent_ns.size();
    const bool fresh = recent > 0 && now_ns - s->recent_ns.back() < 1'000'000'000;
    streams[name] = {{"received", s->received}, {"rate_hz", fresh ? static_cast<double>(recent) : 0.0},
                     {"last_stamp_ns", s->last_stamp_ns}, {"bodies", bodies},
                     {"last_age_s", s->last_stamp_ns > 0 ? static_cast<double>(now_ns - s->last_stamp_ns) * 1e-9 : -1.0}};
  }
  status["streams"] = streams;
  status["disk"] = DiskStatus(options_.sessions_dir);
  return status;
}

}  // namespace mocap::capture
