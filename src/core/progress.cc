#include "core/progress.h"

#include <algorithm>
#include <chrono>
#include <utility>

#include "core/check.h"

namespace mocap {

Progress::Progress(ProgressSink* sink, std::string task, int64_t total, std::string unit, double min_interval_s)
    : sink_(sink),
      task_(std::move(task)),
      total_(total),
      unit_(std::move(unit)),
      min_interval_ns_(static_cast<int64_t>(min_interval_s * 1e9)),
      start_ns_(0) {
  if (total < 0) throw InputError(task_, Str("progress total must be >= 0 (0 = unknown), not ", total));
  if (!(min_interval_s >= 0))
    throw InputError(task_, Str("progress min_interval_s must be >= 0, not ", min_interval_s));
  start_ns_ = NowNs();
  // next_report_ns_ = 0 makes the first Advance() report at once.
}

Progress::~Progress() {
  try {
    Finish();
  } catch (...) {
    // A sink that throws from a destructor would terminate the program; the line is lost instead.
  }
}

int64_t Progress::NowNs() const {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void Progress::Advance(int64_t n) {
  if (sink_ == nullptr || n <= 0) return;
  const int64_t done_now = done_.fetch_add(n, std::memory_order_relaxed) + n;
  const bool reached_total = total_ > 0 && done_now >= total_ && done_now - n < total_;
  const int64_t now_ns = NowNs();
  if (!reached_total && now_ns < next_report_ns_.load(std::memory_order_relaxed)) return;
  std::lock_guard lock(report_mutex_);
  if (finished_) return;
  // Another thread may have reported while this one waited for the lock.
  if (!reached_total && now_ns < next_report_ns_.load(std::memory_order_relaxed)) return;
  next_report_ns_.store(now_ns + min_interval_ns_, std::memory_order_relaxed);
  ReportLocked(now_ns, false);
}

void Progress::Finish() {
  if (sink_ == nullptr) return;
  std::lock_guard lock(report_mutex_);
  if (finished_) return;
  finished_ = true;
  ReportLocked(NowNs(), true);
}

void Progress::ReportLocked(int64_t now_ns, bool finished) {
  ProgressUpdate update;
  update.task = task_;
  // Read under the lock: every earlier report read a value no larger, so `done` never goes back.
  update.done = done_.load(std::memory_order_relaxed);
  update.total = total_;
  update.unit = unit_;
  update.elapsed_s = static_cast<double>(std::max<int64_t>(0, now_ns - start_ns_)) * 1e-9;
  update.rate_per_s = update.elapsed_s > 0 ? static_cast<double>(update.done) / update.elapsed_s : 0.0;
  if (total_ > 0 && update.done >= total_) {
    update.eta_s = 0;
  } else if (total_ > 0 && update.rate_per_s > 0) {
    update.eta_s = static_cast<double>(total_ - update.done) / update.rate_per_s;
  }
  update.finished = finished;
  sink_->Report(update);
}

}  // namespace mocap
