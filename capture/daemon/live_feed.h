#pragma once
// The live page's data: a snapshot of the daemon a few times a second (status, the newest events, the
// thumbnails' legends, the disk's time until full), built once per tick on its own thread and handed
// as the same text to every viewer (Server-Sent Events or a poll). A viewer only ever copies a shared
// pointer under a short lock and writes on its own connection, so a slow or vanished viewer costs its
// own worker until the write timeout and nothing else; the recording never waits for a viewer.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>

#include "capture/daemon/daemon.h"

namespace mocap::capture {

struct LiveFeedOptions {
  double rate_hz = 2;            ///< snapshots per second
  size_t events_per_snapshot = 50;
  double disk_rate_window_s = 10;  ///< the write rate behind "time until full" is measured over this
  void check() const;
};

class LiveFeed {
 public:
  LiveFeed(CaptureDaemon& daemon, const LiveFeedOptions& options);
  ~LiveFeed();  ///< Stop()
  LiveFeed(const LiveFeed&) = delete;
  LiveFeed& operator=(const LiveFeed&) = delete;

  /// Ends the snapshots and wakes every waiting viewer (which then ends its stream).
  void Stop();

  struct Published {
    int64_t version = 0;  ///< 0: none yet
    std::shared_ptr<const std::string> json;
  };
  /// Waits up to `timeout` for a snapshot newer than version `seen`; the same version on timeout,
  /// nullopt once stopped.
  std::optional<Published> WaitNewer(int64_t seen, std::chrono::milliseconds timeout);
  Published Latest() const;

  /// Stream slots, so that viewers cannot take every worker of the control server.
  bool TryAddViewer(int max_viewers);
  void RemoveViewer();
  int viewers() const;

 private:
  void Loop();
  nlohmann::json Snapshot();
  nlohmann::json DiskEstimate(const nlohmann::json& disk, int64_t now_ns);
  void NoteDrops(const nlohmann::json& status, int64_t now_ns);

  CaptureDaemon& daemon_;
  LiveFeedOptions options_;
  mutable std::mutex mutex_;  // guards published_, stop_, viewers_
  std::condition_variable changed_;
  Published published_;
  bool stop_ = false;
  int viewers_ = 0;
  // The feed's thread only:
  std::deque<std::pair<int64_t, uint64_t>> free_bytes_;  // (stamp_ns, free bytes)
  std::map<std::string, int64_t> dropped_seen_;
  std::thread thread_;
};

}  // namespace mocap::capture
