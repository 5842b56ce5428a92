#pragma once
// A registration backend's own index of a scene (a kd-tree, the scene with normals), built once per scene
// and shared by every registration against it: the acquisition registers some thirty hypotheses against one
// scene, from several threads at once, and a fair user of a kd-tree library builds its tree once, not per
// hypothesis. Keyed by PointGrid::id(), which no later grid reuses (an address would be: the next record's
// grid can land where the last one was freed).
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <utility>

#include "validate/point_grid.h"

namespace mocap::bench {

template <typename Index>
class SceneIndexCache {
 public:
  /// Keeps the indices of the last `capacity` scenes (one per thread at work suffices).
  explicit SceneIndexCache(size_t capacity = 8) : capacity_(capacity) {}

  /// The index of `grid`, made by build(grid) on first use; a thread asking while another builds it waits
  /// for that build rather than making its own.
  std::shared_ptr<const Index> Get(const PointGrid& grid,
                                   const std::function<std::shared_ptr<const Index>(const PointGrid&)>& build) const {
    std::promise<std::shared_ptr<const Index>> promise;
    std::shared_future<std::shared_ptr<const Index>> known;
    {
      std::lock_guard lock(mutex_);
      for (const auto& [id, index] : entries_)
        if (id == grid.id()) known = index;  // built, or being built by another thread
      if (!known.valid()) {
        entries_.emplace_back(grid.id(), promise.get_future().share());
        if (entries_.size() > capacity_) entries_.pop_front();
      }
    }
    if (known.valid()) return known.get();
    try {
      std::shared_ptr<const Index> index = build(grid);
      promise.set_value(index);
      return index;
    } catch (...) {
      promise.set_exception(std::current_exception());
      throw;
    }
  }

 private:
  size_t capacity_;
  mutable std::mutex mutex_;
  mutable std::deque<std::pair<uint64_t, std::shared_future<std::shared_ptr<const Index>>>> entries_;
};

}  // namespace mocap::bench
