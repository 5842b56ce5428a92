#include "capture/daemon/clock_samples.h"

#include "core/check.h"

namespace mocap::capture {
namespace {

template <typename T>
void KeepEven(std::vector<T>& values) {
  size_t kept = 0;
  for (size_t i = 0; i < values.size(); i += 2) values[kept++] = values[i];
  values.resize(kept);
}

}  // namespace

void ClockSamples::Add(const std::string& stream, int64_t device, int64_t host_ns) {
  Stream& s = streams_[stream];
  if (s.has_last && device == s.last_device) return;
  s.has_last = true;
  s.last_device = device;
  if (s.seen++ % s.stride != 0) return;
  s.device.push_back(device);
  s.host_ns.push_back(host_ns);
  if (s.device.size() >= max_pairs_) {
    KeepEven(s.device);
    KeepEven(s.host_ns);
    s.stride *= 2;
  }
}

std::map<std::string, ClockFit> ClockSamples::Fit() const {
  std::map<std::string, ClockFit> fits;
  for (const auto& [stream, s] : streams_) {
    if (s.device.size() < 2) continue;
    try {
      fits[stream] = FitClock(s.device, s.host_ns);
    } catch (const InputError&) {
      // A device clock that never changed (a source without one): nothing to fit.
    }
  }
  return fits;
}

}  // namespace mocap::capture
