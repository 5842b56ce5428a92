#pragma once
// Records one session from any producers: the public in-process API of the capture pipeline (used by
// the daemon, the benchmark and the simulated rig). Producers push into bounded queues (PushFrame /
// PushSample / PushEvent, never blocking): one frame queue per camera of the manifest, so a camera whose
// frames cost more to encode (PNG colour) never makes another (JPEG colour as it came) drop, and one
// queue for tracker samples and events; one writer thread per queue hands the items to the
// SessionWriter (src/session/writer.h). When a queue is full the item is dropped, counted per stream
// and logged as a "drop" event (at most one per stream per drop_event_interval_ms, with the count):
// never silently. A write error (a full disk, EIO) stops the session: nothing more is written, the
// manifest stays complete = false, and error() says what failed (the writer's message names the file).
// On a clean stop every stream's device clock is fitted onto the host clock (camera: device_ticks,
// tracker: device_frame; clock_samples.h) and the fits go into the manifest's clock_fits.
//
//   auto recorder = Recorder::Start({.session_dir = "sessions/S"}, manifest);
//   recorder->PushFrame({"kinect1", record, bgr, depth_mm});   // from any thread
//   RecorderSummary summary = recorder->Stop();                 // drains, closes, complete = true
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "capture/daemon/bounded_queue.h"
#include "capture/daemon/clock_samples.h"
#include "capture/daemon/source.h"
#include "session/writer.h"

namespace mocap::capture {

struct RecorderOptions {
  std::filesystem::path session_dir;  ///< created; must not exist or be empty
  int frame_queue = 32;      ///< camera frames waiting for the writer, per camera (RGB-D 640x480: ~1.5 MB each)
  int sample_queue = 8192;   ///< tracker samples and events waiting (one sample per body per tracker frame)
  int drop_event_interval_ms = 1000;  ///< at most one "drop" event per stream per interval
  SessionWriterOptions writer{};
  /// Throws InputError naming the bad field.
  void check() const;
};

/// Counters of one stream (a camera or a tracker).
struct StreamCounters {
  int64_t received = 0;  ///< pushed by producers
  int64_t written = 0;   ///< handed to the session writer
  int64_t dropped = 0;   ///< refused because the queue was full (or after a write error)
};

struct RecorderSummary {
  std::filesystem::path session_dir;
  bool complete = false;   ///< closed cleanly (manifest complete = true)
  std::string error;       ///< the write error that stopped the session, "" if none
  std::map<std::string, StreamCounters> streams;
  int64_t events_written = 0;
  int64_t events_dropped = 0;
  int64_t duration_ns = 0;
  nlohmann::json ToJson() const;
};

class Recorder final : public CaptureSink {
 public:
  /// Creates the session (SessionWriter::Create) and starts the writer threads. Throws InputError when
  /// the options or manifest are invalid or the folder cannot be created.
  static std::unique_ptr<Recorder> Start(const RecorderOptions& options, const SessionManifest& manifest);
  ~Recorder() override;  ///< stops if still running

  void PushFrame(CapturedFrame&& frame) override;
  void PushSample(CapturedSample&& sample) override;
  void PushEvent(EventRecord&& event) override;

  /// Stops accepting, writes what is queued, closes the session. Idempotent; never throws (a failure
  /// is in the summary's error).
  RecorderSummary Stop();
  /// The summary so far (counters are live).
  RecorderSummary Snapshot() const;
  /// The error that stopped the session, if one did.
  std::optional<std::string> error() const;
  bool failed() const { return failed_.load(); }
  /// Frames queued for all cameras, or for one (0 for a camera not in the manifest).
  size_t frame_queue_depth() const;
  size_t frame_queue_depth(const std::string& camera) const;
  size_t sample_queue_depth() const { return records_.size(); }
  nlohmann::json QueueStatus() const;

 private:
  using RecordItem = std::variant<CapturedSample, EventRecord>;
  Recorder(const RecorderOptions& options, std::unique_ptr<SessionWriter> writer);
  void FrameLoop(const std::string& camera, BoundedQueue<CapturedFrame>& queue);
  void WriteFrame(CapturedFrame& frame);
  void RecordLoop();
  void WriteRecord(RecordItem& item);
  void FlushDropEvents(bool final_flush);
  void CountDrop(const std::string& stream, int64_t stamp_ns);
  void Fail(const std::string& message);
  StreamCounters& counters(const std::string& stream);  // mutex_ held

  RecorderOptions options_;
  std::unique_ptr<SessionWriter> writer_;
  std::map<std::string, std::unique_ptr<BoundedQueue<CapturedFrame>>> frames_;  // per camera; fixed at Start
  BoundedQueue<RecordItem> records_;
  std::vector<std::thread> frame_threads_;
  std::thread record_thread_;
  mutable std::mutex mutex_;  // guards everything below
  std::map<std::string, StreamCounters> streams_;
  ClockSamples clocks_;
  int64_t last_drop_flush_ns_ = 0;
  std::map<std::string, int64_t> unreported_drops_;
  int64_t events_written_ = 0, events_dropped_ = 0;
  int64_t start_ns_ = 0, stop_ns_ = 0;
  std::string error_;
  std::atomic<bool> failed_{false};
  bool stopped_ = false;
  bool complete_ = false;
};

}  // namespace mocap::capture
