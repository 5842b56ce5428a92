#pragma once
// Frames written in parallel by every exporter: each frame's files are its own, so frames are handed to
// worker threads one at a time (a slow frame does not hold up a fixed chunk).
#include <cstddef>
#include <functional>

namespace mocap::exporters {

/// `requested`, or one per core when 0.
int WorkerThreads(int requested);

/// Runs work(i) for i in [0, n) on WorkerThreads(threads) threads. Items are handed out in increasing
/// order and none after a failure, so the failure rethrown is the one of the lowest i whatever the
/// scheduling (the same input gives the same error).
void ParallelFor(size_t n, int threads, const std::function<void(size_t)>& work);

}  // namespace mocap::exporters
