#pragma once
// CPU clocks for the benchmarks: the whole process's (all threads, user + system) and the calling
// thread's, in seconds.
#include <time.h>

namespace mocap::bench {

inline double SecondsOf(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

inline double ProcessCpuS() { return SecondsOf(CLOCK_PROCESS_CPUTIME_ID); }
inline double ThreadCpuS() { return SecondsOf(CLOCK_THREAD_CPUTIME_ID); }

}  // namespace mocap::bench
