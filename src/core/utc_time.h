#pragma once
// The wall-clock time, for files that record when they were made (manifests, run.json); every stage's
// own time axis is the host monotonic clock (core/clock.h).
#include <ctime>
#include <string>

namespace mocap {

/// Now as ISO 8601 UTC with seconds, e.g. "2026-12-02T10:00:00Z".
inline std::string NowUtcIso8601() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

}  // namespace mocap
