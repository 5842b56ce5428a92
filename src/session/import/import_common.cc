#include "session/import/import_common.h"

#include "core/check.h"
#include "session/writer.h"

namespace mocap::import {

void WriteBodySamples(SessionWriter& writer, const std::string& tracker, std::span<const TrackerRecord> records,
                      int64_t gap_limit_ns, ImportSummary& summary) {
  if (records.empty()) return;
  BodySummary& body = summary.bodies[tracker + "/" + records.front().body];
  for (size_t i = 0; i < records.size(); ++i) {
    const TrackerRecord& r = records[i];
    writer.WriteTrackerSample(tracker, r);
    ++body.samples;
    ++body.status_counts[std::string(ToString(r.status))];
    if (i == 0) continue;
    const int64_t previous_ns = records[i - 1].stamp_ns;
    MOCAP_CHECK(r.stamp_ns >= previous_ns, "records of ", r.body, " are not sorted by time");
    const std::string stream = tracker + "/" + r.body;
    if (r.stamp_ns == previous_ns) {
      ++body.duplicate_stamps;
      writer.WriteEvent({r.stamp_ns, "duplicate_stamp", stream, Str("two samples at the same time (source sample ", i, ")")});
    } else if (r.stamp_ns - previous_ns > gap_limit_ns) {
      body.gaps.push_back({previous_ns, r.stamp_ns});
      writer.WriteEvent({previous_ns, "gap", stream,
                         Str("no samples for ", static_cast<double>(r.stamp_ns - previous_ns) * 1e-9, " s")});
    }
  }
  summary.tracker_samples += static_cast<int64_t>(records.size());
}

void CheckOutputFolder(const std::filesystem::path& out) {
  if (out.empty()) throw InputError("--out", "no session folder given");
  if (std::filesystem::exists(out) &&
      (!std::filesystem::is_directory(out) || !std::filesystem::is_empty(out)))
    throw InputError(out.string(), "the session folder exists and is not empty; choose a new --out");
}

}  // namespace mocap::import
