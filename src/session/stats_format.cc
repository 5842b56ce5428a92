// The human-readable form of SessionStats (`mocaplabel info` without --json).
#include <algorithm>
#include <cstdarg>
#include <cstdio>

#include "session/stats.h"

namespace mocap {
namespace {

void Append(std::string* out, const char* format, ...) __attribute__((format(printf, 2, 3)));
void Append(std::string* out, const char* format, ...) {
  char line[1024];
  va_list args;
  va_start(args, format);
  std::vsnprintf(line, sizeof(line), format, args);
  va_end(args);
  *out += line;
}

double LongestS(const std::vector<TimeSpan>& spans) {
  int64_t longest = 0;
  for (const auto& span : spans) longest = std::max(longest, span.end_ns - span.start_ns);
  return static_cast<double>(longest) * 1e-9;
}

std::string Timing(const StreamTiming& timing, double gap_limit_s) {
  std::string out;
  Append(&out, "%.2f Hz over %.2f s, %zu gaps > %.2f s", timing.rate_hz, timing.duration_s, timing.gaps.size(),
         gap_limit_s);
  if (!timing.gaps.empty()) Append(&out, " (longest %.2f s)", LongestS(timing.gaps));
  if (timing.duplicates > 0) Append(&out, ", %lld repeated stamps", static_cast<long long>(timing.duplicates));
  return out;
}

}  // namespace

std::string FormatSessionStats(const SessionStats& stats) {
  std::string out;
  const double gap_limit_s = static_cast<double>(stats.gap_limit_ns) * 1e-9;
  Append(&out, "session %s: %s, format %d, written by mocaplabel %s on %s, source \"%s\"\n", stats.dir.c_str(),
         stats.complete ? "complete" : "INCOMPLETE (the writer did not close)", stats.format_version,
         stats.software_version.c_str(), stats.created_utc.c_str(), stats.source.c_str());
  Append(&out, "frames with colour and depth: %lld", static_cast<long long>(stats.frames));
  if (stats.frames_with_pose) Append(&out, ", with a camera pose: %lld", static_cast<long long>(*stats.frames_with_pose));
  Append(&out, "; missing image files: %zu\n", stats.missing_files.size());
  for (const auto& camera : stats.cameras) {
    Append(&out, "camera %s: %lld records, colour %lld/%lld present, depth %lld/%lld present, ", camera.name.c_str(),
           static_cast<long long>(camera.records), static_cast<long long>(camera.color_present),
           static_cast<long long>(camera.color_listed), static_cast<long long>(camera.depth_present),
           static_cast<long long>(camera.depth_listed));
    if (camera.frames_subset)  // no rate and no drops: the frames were chosen, not streamed
      Append(&out, "a chosen subset of the recording's frames\n");
    else
      Append(&out, "%s, %lld dropped\n", Timing(camera.timing, gap_limit_s).c_str(),
             static_cast<long long>(camera.dropped_frames));
    for (const auto& [failure, count] : camera.pose_failures)
      Append(&out, "  no camera pose (%s): %lld frames\n", failure.c_str(), static_cast<long long>(count));
  }
  for (const auto& body : stats.bodies) {
    Append(&out, "body %s (tracker %s): %lld samples, %s, %zu dropouts\n  status:", body.body.c_str(),
           body.tracker.c_str(), static_cast<long long>(body.samples), Timing(body.timing, gap_limit_s).c_str(),
           body.dropouts.size());
    for (const auto& [status, count] : body.status_counts)
      if (count > 0) Append(&out, " %s %lld", status.c_str(), static_cast<long long>(count));
    out += "\n";
  }
  for (const auto& [device, fit] : stats.clock_fits)
    Append(&out, "clock %s: residual rms %.1f us, max %.1f us, %d of %d samples inliers\n", device.c_str(),
           fit.residual_rms_ns * 1e-3, fit.residual_max_ns * 1e-3, fit.inliers, fit.samples);
  if (!stats.event_counts.empty()) {
    out += "events:";
    for (const auto& [kind, count] : stats.event_counts) Append(&out, " %s %lld", kind.c_str(), static_cast<long long>(count));
    out += "\n";
  }
  for (const auto& stream : stats.streams) {
    if (stream.torn_tail) Append(&out, "warning: %s: an incomplete last record was ignored\n", stream.file.c_str());
    if (stream.corrupt_lines > 0)
      Append(&out, "warning: %s: %lld corrupt records skipped\n", stream.file.c_str(),
             static_cast<long long>(stream.corrupt_lines));
  }
  const size_t shown = std::min<size_t>(stats.missing_files.size(), 5);
  for (size_t i = 0; i < shown; ++i) Append(&out, "missing: %s\n", stats.missing_files[i].c_str());
  if (stats.missing_files.size() > shown)
    Append(&out, "missing: ... and %zu more (see --json)\n", stats.missing_files.size() - shown);
  return out;
}

}  // namespace mocap
