#pragma once
// (device clock, host receive time) pairs of each stream, kept for the clock fit the recorder writes
// into the manifest when a session closes (DESIGN.md "Time": device clocks are mapped onto the host
// clock by regression; core/clock.h FitClock). Bounded: past max_pairs, every other pair is dropped and
// only every 2nd, 4th, ... new one kept, so an hour at 4 kHz costs no more than a minute.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/clock.h"

namespace mocap::capture {

class ClockSamples {
 public:
  explicit ClockSamples(size_t max_pairs = 20000) : max_pairs_(max_pairs) {}

  /// One item of `stream`. A tracker delivers one record per body with the same frame number: repeats
  /// of the stream's last device value are ignored (the first receive time of a frame is kept).
  void Add(const std::string& stream, int64_t device, int64_t host_ns);

  /// Robust fits of the streams whose device clock took at least two values (core/clock.h); a stream
  /// whose fit fails (too few distinct values) is left out.
  std::map<std::string, ClockFit> Fit() const;

 private:
  struct Stream {
    std::vector<int64_t> device, host_ns;
    int64_t stride = 1, seen = 0;
    bool has_last = false;
    int64_t last_device = 0;
  };
  size_t max_pairs_;
  std::map<std::string, Stream> streams_;
};

}  // namespace mocap::capture
