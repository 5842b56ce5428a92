#include "session/import/import_common.h"

#include <nlohmann/json.hpp>
#include <system_error>

#include "core/check.h"
#include "core/text.h"
#include "session/durable_file.h"
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

double CheckInRange(double value, const NumberRange& range, const std::string& name) {
  if (!(value >= range.min && value <= range.max))  // also refuses NaN
    throw InputError(name, Str("must be between ", range.min, " and ", range.max, " ", range.unit, ", got ", value));
  return value;
}

void CheckOutputFolder(const std::filesystem::path& out) {
  if (out.empty()) throw InputError("--out", "no session folder given");
  if (std::filesystem::exists(out) &&
      (!std::filesystem::is_directory(out) || !std::filesystem::is_empty(out)))
    throw InputError(out.string(), "the session folder exists and is not empty; choose a new --out");
}

namespace {

// "s/" and "./s" name the same folder as "s"; the partial folder and the rename need the bare name.
std::filesystem::path BareFolder(const std::filesystem::path& out) {
  std::filesystem::path bare = out.lexically_normal();
  return bare.has_filename() ? bare : bare.parent_path();
}

}  // namespace

std::filesystem::path PartialFolder(const std::filesystem::path& out) {
  return std::filesystem::path(BareFolder(out)).concat(".partial");
}

namespace {

// A `<out>.partial` left by a killed import is ours to replace; anything else there is the user's.
void ClearStalePartial(const std::filesystem::path& partial) {
  std::error_code error;
  if (!std::filesystem::exists(partial, error)) return;
  const bool ours = std::filesystem::is_directory(partial, error) &&
                    (std::filesystem::is_empty(partial, error) || std::filesystem::exists(partial / "manifest.json", error));
  if (!ours)
    throw InputError(partial.string(), "exists and is not a session left by an interrupted import; move it away");
  std::filesystem::remove_all(partial, error);
  if (error) throw InputError(partial.string(), Str("cannot remove the leftover of an interrupted import: ", error.message()));
}

void Publish(const std::filesystem::path& partial, const std::filesystem::path& out) {
  std::error_code error;
  std::filesystem::rename(partial, BareFolder(out), error);  // replaces an empty `out` folder
  if (error)
    throw InputError(out.string(), Str("cannot rename ", partial.string(), " into place: ", error.message()));
  const std::filesystem::path parent = std::filesystem::absolute(BareFolder(out)).parent_path();
  SyncDirectory(parent);
}

void WriteAndPublish(const std::filesystem::path& out, const std::filesystem::path& source, SessionManifest& manifest,
                     const std::function<void(SessionWriter&, const std::filesystem::path&)>& write) {
  const std::filesystem::path partial = PartialFolder(out);
  ClearStalePartial(partial);
  // The source path is only shown to the user; a path in another encoding must not stop JSON storing it.
  manifest.source = TextToUtf8(manifest.source);
  try {
    manifest.check();
  } catch (const InputError& e) {
    throw InputError(source.string(), e.what());
  }
  try {
    {
      auto writer = SessionWriter::Create(partial, manifest);
      write(*writer, partial);
      writer->Close();
    }  // the writer is gone (its threads joined) before its folder is renamed or removed
    Publish(partial, out);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove_all(partial, ignored);
    throw;
  }
}

}  // namespace

void PublishSession(const std::filesystem::path& out, const std::filesystem::path& source, SessionManifest manifest,
                    const std::function<void(SessionWriter&, const std::filesystem::path& dir)>& write) {
  CheckOutputFolder(out);
  try {
    WriteAndPublish(out, source, manifest, write);
  } catch (const nlohmann::json::exception& e) {
    // A safety net: text from the source that JSON cannot hold is transcoded where it is read.
    throw InputError(source.string(), Str("cannot store the session: ", e.what()));
  }
}

}  // namespace mocap::import
