#include "capture/daemon/live_feed.h"

#include "core/check.h"

namespace mocap::capture {

void LiveFeedOptions::check() const {
  if (!(rate_hz >= 0.2 && rate_hz <= 20)) throw InputError("live feed rate", Str(rate_hz, " Hz is not in 0.2..20"));
  if (events_per_snapshot == 0) throw InputError("live feed", "events_per_snapshot must be positive");
  if (!(disk_rate_window_s > 0)) throw InputError("live feed", "disk_rate_window_s must be positive");
}

LiveFeed::LiveFeed(CaptureDaemon& daemon, const LiveFeedOptions& options) : daemon_(daemon), options_(options) {
  options_.check();
  thread_ = std::thread([this] { Loop(); });
}

LiveFeed::~LiveFeed() { Stop(); }

void LiveFeed::Stop() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::optional<LiveFeed::Published> LiveFeed::WaitNewer(int64_t seen, std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, timeout, [&] { return stop_ || published_.version != seen; });
  if (stop_) return std::nullopt;
  return published_;
}

LiveFeed::Published LiveFeed::Latest() const {
  std::lock_guard lock(mutex_);
  return published_;
}

bool LiveFeed::TryAddViewer(int max_viewers) {
  std::lock_guard lock(mutex_);
  if (stop_ || viewers_ >= max_viewers) return false;
  ++viewers_;
  return true;
}

void LiveFeed::RemoveViewer() {
  std::lock_guard lock(mutex_);
  --viewers_;
}

int LiveFeed::viewers() const {
  std::lock_guard lock(mutex_);
  return viewers_;
}

void LiveFeed::Loop() {
  const auto period = std::chrono::nanoseconds(static_cast<int64_t>(1e9 / options_.rate_hz));
  std::unique_lock lock(mutex_);
  while (!stop_) {
    lock.unlock();
    auto json = std::make_shared<const std::string>(Snapshot().dump());
    lock.lock();
    published_ = {published_.version + 1, std::move(json)};
    changed_.notify_all();
    changed_.wait_for(lock, period, [this] { return stop_; });
  }
}

// Free space and, from how fast it shrank over the last window, the time until the disk is full (null
// while it does not shrink measurably).
nlohmann::json LiveFeed::DiskEstimate(const nlohmann::json& disk, int64_t now_ns) {
  nlohmann::json out = disk;
  out["write_bytes_per_s"] = nullptr;
  out["seconds_to_full"] = nullptr;
  if (!disk.contains("free_bytes")) return out;
  const auto free_bytes = disk["free_bytes"].get<uint64_t>();
  free_bytes_.emplace_back(now_ns, free_bytes);
  const auto window_ns = static_cast<int64_t>(options_.disk_rate_window_s * 1e9);
  while (free_bytes_.size() > 2 && free_bytes_.front().first < now_ns - window_ns) free_bytes_.pop_front();
  const auto& [then_ns, then_free] = free_bytes_.front();
  const double dt_s = static_cast<double>(now_ns - then_ns) * 1e-9;
  if (dt_s < 1.0) return out;
  const double rate = (static_cast<double>(then_free) - static_cast<double>(free_bytes)) / dt_s;
  out["write_bytes_per_s"] = std::max(rate, 0.0);
  if (rate > 1024) out["seconds_to_full"] = static_cast<double>(free_bytes) / rate;
  return out;
}

// The recorder writes its drop events into the session; the page learns of drops from the counters.
void LiveFeed::NoteDrops(const nlohmann::json& status, int64_t now_ns) {
  if (!status["session"].is_object() || !status["session"].contains("streams")) {
    dropped_seen_.clear();
    return;
  }
  for (const auto& [stream, counters] : status["session"]["streams"].items()) {
    const int64_t dropped = counters.value("dropped", int64_t{0});
    int64_t& seen = dropped_seen_[stream];
    if (dropped > seen)
      daemon_.live().OnEvent({now_ns, "drop", stream,
                              Str(dropped - seen, " item(s) dropped (", dropped, " in this session): the writer is behind")});
    seen = dropped;
  }
}

nlohmann::json LiveFeed::Snapshot() {
  const int64_t now_ns = MonotonicNowNs();
  nlohmann::json status = daemon_.Status();
  NoteDrops(status, now_ns);
  status["disk"] = DiskEstimate(status["disk"], now_ns);
  nlohmann::json thumbnails = nlohmann::json::array();
  for (const auto& t : daemon_.live().Thumbnails()) {
    if (!t) continue;
    thumbnails.push_back({{"camera", t->camera}, {"seq", t->seq}, {"frame", t->frame}, {"stamp_ns", t->stamp_ns},
                          {"width", t->width}, {"height", t->height}, {"labels", !t->labels_png.empty()},
                          {"legend", t->legend}, {"label_error", t->label_error}});
  }
  return {{"status", status}, {"events", daemon_.live().Events(options_.events_per_snapshot)},
          {"thumbnails", thumbnails}, {"viewers", viewers()}, {"now_ns", now_ns}};
}

}  // namespace mocap::capture
