#pragma once
// Progress of long work (label, validate, sim record, demo, import, export): a thread-safe counter
// per task that reports to a sink. The core holds the interface only; the sinks that draw a terminal
// line or write JSON objects live in src/pipeline (progress_sinks.h), so the core stays free of I/O.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

namespace mocap {

/// One snapshot of a task's progress, as a sink receives it.
struct ProgressUpdate {
  std::string task;             // "label", "validate", "sim record", ...
  int64_t done = 0, total = 0;  // total 0 = unknown
  std::string unit;             // "frames", "records", "shards"
  double elapsed_s = 0, rate_per_s = 0;  // rate over the whole task so far
  double eta_s = -1;                     // -1 unknown
  bool finished = false;
};

/// Where updates go (a terminal line, JSON lines, a test's recorder). Report() may be called from any
/// thread, but never concurrently for the same Progress.
class ProgressSink {
 public:
  virtual ~ProgressSink() = default;
  virtual void Report(const ProgressUpdate& update) = 0;
};

/// A task's counter. Thread-safe Advance(); reports to the sink at most every `min_interval_s` (and
/// always the first update, the one that reaches `total`, and Finish()), so a hot loop can call it per
/// frame. A null sink makes every call a cheap no-op. Reported `done` values are monotone
/// non-decreasing.
class Progress {
 public:
  Progress(ProgressSink* sink, std::string task, int64_t total, std::string unit = "frames",
           double min_interval_s = 0.25);
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  /// Finish()es if the owner did not (an early return or an exception still ends the line).
  ~Progress();

  void Advance(int64_t n = 1);
  /// Reports finished = true, once; later calls and Advance() after it report nothing.
  void Finish();

  /// Counted so far; stays 0 with a null sink, where Advance() does nothing at all.
  int64_t done() const { return done_.load(std::memory_order_relaxed); }

 private:
  int64_t NowNs() const;
  /// Reports the counter as it is now; called with report_mutex_ held.
  void ReportLocked(int64_t now_ns, bool finished);

  ProgressSink* sink_;
  std::string task_;
  int64_t total_;
  std::string unit_;
  int64_t min_interval_ns_;
  int64_t start_ns_;
  std::atomic<int64_t> done_{0};
  // Advance() reads this without the lock, so the common case (not yet time to report) takes no lock.
  std::atomic<int64_t> next_report_ns_{0};
  std::mutex report_mutex_;
  bool finished_ = false;  // guarded by report_mutex_
};

}  // namespace mocap
