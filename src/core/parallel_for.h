#pragma once
// An OpenMP loop whose bodies may throw. The including target links OpenMP::OpenMP_CXX.
#include <exception>
#include <mutex>
#include <omp.h>

namespace mocap {

/// Runs body(i) for i in [0, n) on OpenMP threads (`threads` <= 0: OpenMP's default), one index at a
/// time; after all finish, the exception of the lowest i that threw is rethrown (the same error
/// whatever the threads' timing).
template <typename Body>
void ParallelFor(int n, int threads, Body body) {
  std::exception_ptr error;
  int error_index = n;
  std::mutex mutex;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads > 0 ? threads : omp_get_max_threads())
  for (int i = 0; i < n; ++i) {
    try {
      body(i);
    } catch (...) {
      std::lock_guard lock(mutex);
      if (i < error_index) error = std::current_exception(), error_index = i;
    }
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace mocap
