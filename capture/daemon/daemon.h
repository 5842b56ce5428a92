#pragma once
// The capture daemon's core, without HTTP: it opens the rig's sources once and keeps them streaming
// (so `status` shows live rates and visible bodies between sessions), and records a session between
// StartSession and StopSession by forwarding everything the sources push to a Recorder. Replays
// (CaptureSource::starts_with_session) are opened at once but started by the first StartSession, after
// its recorder exists, so their first frame is in the session; they then play on like live devices.
// A session that a write error stopped (a full disk) is closed at once; its error stays in status()
// and is returned by the next StopSession.
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "capture/daemon/live_view.h"
#include "capture/daemon/recorder.h"
#include "capture/daemon/source.h"

namespace mocap::capture {

struct CaptureDaemonOptions {
  std::filesystem::path sessions_dir;  ///< sessions are created as <sessions_dir>/<name>
  std::string rig_name{};                ///< recorded in the manifest's extra
  nlohmann::json manifest_extra = nlohmann::json::object();  ///< more fields for the manifest's extra
  RecorderOptions recorder{};           ///< session_dir is filled per session
  LiveViewOptions live{};               ///< the live page's thumbnails and events
  /// Draws the labels on the live thumbnails (null: thumbnails without labels).
  std::shared_ptr<FrameLabeller> labeller{};
  void check() const;
};

/// Thrown for a request that cannot be served in the daemon's state (start while recording, stop
/// while idle): the control API answers 409 with the message.
class StateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class CaptureDaemon final : public CaptureSink {
 public:
  /// Opens every source and starts the live ones (DeviceError / InputError from the first that fails).
  CaptureDaemon(const CaptureDaemonOptions& options, std::vector<std::unique_ptr<CaptureSource>> sources);
  ~CaptureDaemon() override;  ///< stops a running session (complete) and closes the sources

  /// Starts recording into <sessions_dir>/<name>, then the replays not started yet. Throws InputError
  /// for a bad name or an existing session, StateError while a session is running.
  nlohmann::json StartSession(const std::string& name);
  /// Stops and closes the running session; returns its summary. StateError when none is running and
  /// none failed since the last stop.
  nlohmann::json StopSession();
  /// Per stream: rate over the last second, totals, drops, visible bodies; queues; disk free; session.
  nlohmann::json Status() const;

  /// The live page's events and thumbnails.
  LiveView& live() { return *live_; }

  void PushFrame(CapturedFrame&& frame) override;
  void PushSample(CapturedSample&& sample) override;
  void PushEvent(EventRecord&& event) override;

 private:
  struct StreamStats;
  SessionManifest BuildManifest() const;
  void StartReplays();  // session_mutex_ not held
  void WatchForFailure();
  StreamStats& stats(const std::string& stream);  // stats_mutex_ held

  CaptureDaemonOptions options_;
  std::unique_ptr<LiveView> live_;  // before the sources: they push into it
  std::vector<std::unique_ptr<CaptureSource>> sources_;
  mutable std::mutex session_mutex_;  // guards recorder_, session_name_, last_summary_
  std::shared_ptr<Recorder> recorder_;
  std::string session_name_;
  std::optional<RecorderSummary> failed_summary_;
  mutable std::mutex stats_mutex_;
  std::map<std::string, std::unique_ptr<StreamStats>> stats_;
  std::mutex replay_mutex_;  // one StartReplays at a time
  std::thread watcher_;
  std::atomic<bool> stop_{false};
};

/// A plain file name usable as a session folder: 1..128 of [A-Za-z0-9._-], not starting with '.'.
/// Throws InputError saying what is wrong.
void CheckSessionName(const std::string& name);

}  // namespace mocap::capture
