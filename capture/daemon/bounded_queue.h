#pragma once
// A bounded multi-producer queue between device threads and a writer thread (COLMAP's JobQueue with a
// non-blocking push). A device thread must never wait for the disk: when the queue is full, TryPush
// refuses the item and the caller counts and logs the drop. Stop() wakes the consumer; Pop() then
// drains what is left before returning nullopt.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>

#include "core/check.h"

namespace mocap::capture {

template <typename T>
class BoundedQueue {
 public:
  /// capacity >= 1 items.
  explicit BoundedQueue(size_t capacity) : capacity_(capacity) { MOCAP_CHECK(capacity >= 1, "queue capacity 0"); }

  /// Appends unless the queue is full or stopped; false means the item was not taken (a drop).
  bool TryPush(T&& item) {
    {
      std::lock_guard lock(mutex_);
      if (stopped_ || items_.size() >= capacity_) return false;
      items_.push_back(std::move(item));
      if (items_.size() > high_water_) high_water_ = items_.size();
    }
    not_empty_.notify_one();
    return true;
  }

  /// Waits for an item; nullopt once the queue is stopped and empty.
  std::optional<T> Pop() {
    std::unique_lock lock(mutex_);
    not_empty_.wait(lock, [&] { return stopped_ || !items_.empty(); });
    if (items_.empty()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    return item;
  }

  /// Refuses further pushes and wakes the consumer.
  void Stop() {
    {
      std::lock_guard lock(mutex_);
      stopped_ = true;
    }
    not_empty_.notify_all();
  }

  /// Drops everything still queued; returns how many items that was.
  size_t Clear() {
    std::lock_guard lock(mutex_);
    const size_t n = items_.size();
    items_.clear();
    return n;
  }

  size_t size() const {
    std::lock_guard lock(mutex_);
    return items_.size();
  }
  size_t high_water() const {
    std::lock_guard lock(mutex_);
    return high_water_;
  }
  size_t capacity() const { return capacity_; }

 private:
  const size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable not_empty_;
  std::deque<T> items_;
  size_t high_water_ = 0;
  bool stopped_ = false;
};

}  // namespace mocap::capture
