#include "session/import/tracker_import.h"

#include <cmath>
#include <set>

#include "core/check.h"
#include "core/text.h"
#include "session/import/motive_csv.h"
#include "session/import/plus_mha.h"
#include "session/writer.h"

namespace mocap::import {
namespace {

std::string SourceName(const std::string& kind, const std::filesystem::path& file) {
  return "import " + kind + " " + std::filesystem::absolute(file).lexically_normal().string();
}

// Body names for PLUS channels: <From> when all channels share one To frame, else the channel name.
std::vector<std::string> PlusBodyNames(const PlusSequence& seq) {
  std::set<std::string> to_frames;
  for (const auto& t : seq.transforms) to_frames.insert(t.to_frame);
  std::vector<std::string> names;
  for (const auto& t : seq.transforms) names.push_back(to_frames.size() == 1 ? t.from_frame : t.name);
  return names;
}

std::vector<TrackerRecord> PlusRecords(const PlusSequence& seq, const PlusTransformTrack& track, const std::string& body) {
  std::vector<TrackerRecord> records;
  for (size_t i = 0; i < track.samples.size(); ++i) {
    TrackerRecord r;
    r.body = body;
    r.status = track.samples[i].status;
    r.device_frame = seq.frames[i].frame_number.value_or(seq.frames[i].index);
    r.stamp_ns = track.samples[i].stamp_ns;
    r.T_frame_body = track.samples[i].pose;
    records.push_back(r);
  }
  return records;
}

void LogPlusStatuses(SessionWriter& writer, const PlusSequence& seq, const PlusTransformTrack& track) {
  for (size_t i = 0; i < track.samples.size(); ++i) {
    const std::string& text = track.source_status[i];
    if (text.empty() || text == "OK") continue;
    writer.WriteEvent({track.samples[i].stamp_ns, "source_status", "plus/" + track.name,
                       Str(track.name, " Seq_Frame", seq.frames[i].index, ": ", text)});
  }
}

std::vector<TrackerRecord> MotiveRecords(const MotiveTake& take, const MotiveRigidBody& body) {
  std::vector<TrackerRecord> records;
  for (size_t i = 0; i < body.samples.size(); ++i) {
    TrackerRecord r;
    r.body = body.name;
    r.status = body.samples[i].status;
    r.device_frame = take.frame_ids[i];
    r.stamp_ns = body.samples[i].stamp_ns;
    r.T_frame_body = body.samples[i].pose;
    if (std::isfinite(body.mean_marker_error_m[i])) r.rms_error_m = body.mean_marker_error_m[i];
    records.push_back(r);
  }
  return records;
}

}  // namespace

void TrackerImportOptions::check() const {
  if (gap_limit_ns <= 0) throw InputError("TrackerImportOptions", "gap_limit_ns must be positive");
}

ImportSummary ImportPlus(const std::filesystem::path& mha_file, const std::filesystem::path& out,
                         const TrackerImportOptions& options) {
  options.check();
  CheckOutputFolder(out);
  const PlusSequence seq = ReadPlusSequence(mha_file);
  if (seq.transforms.empty()) throw InputError(mha_file.string(), "the sequence holds no <From>To<To>Transform channel");
  const auto bodies = PlusBodyNames(seq);
  SessionManifest manifest;
  manifest.software_version = options.software_version;
  manifest.source = SourceName("plus", mha_file);
  manifest.trackers.push_back({"plus", "plus_sequence", "", "tracker", bodies});
  nlohmann::json channels = nlohmann::json::object();
  for (size_t k = 0; k < bodies.size(); ++k)
    channels[bodies[k]] = {{"channel", seq.transforms[k].name}, {"from", seq.transforms[k].from_frame}, {"to", seq.transforms[k].to_frame}};
  manifest.extra["plus"] = {{"file", mha_file.filename().string()}, {"channels", channels},
                            {"ignored_fields", seq.ignored_fields}, {"translation_unit_in_file", "mm"}};

  ImportSummary summary;
  summary.session = out;
  for (const auto& field : seq.ignored_fields)
    summary.notes.push_back("per-frame field " + QuoteForMessage(field) + " is not a <From>To<To>Transform channel: not imported");
  PublishSession(out, mha_file, manifest, [&](SessionWriter& writer, const std::filesystem::path&) {
    Progress progress(options.progress, "import", static_cast<int64_t>(bodies.size()), "bodies");
    for (size_t k = 0; k < bodies.size(); ++k, progress.Advance()) {
      WriteBodySamples(writer, "plus", PlusRecords(seq, seq.transforms[k], bodies[k]), options.gap_limit_ns, summary);
      LogPlusStatuses(writer, seq, seq.transforms[k]);
    }
  });
  return summary;
}

ImportSummary ImportMotive(const std::filesystem::path& csv_file, const std::filesystem::path& out,
                           const TrackerImportOptions& options) {
  options.check();
  CheckOutputFolder(out);
  const MotiveTake take = ReadMotiveCsv(csv_file, {.keep_markers = false});
  if (take.rigid_bodies.empty()) throw InputError(csv_file.string(), "the export holds no rigid body");
  SessionManifest manifest;
  manifest.software_version = options.software_version;
  manifest.source = SourceName("motive", csv_file);
  TrackerStreamInfo tracker{"motive", "optitrack_motive", "", "tracker", {}};
  nlohmann::json ids = nlohmann::json::object();
  for (const auto& body : take.rigid_bodies) {
    tracker.bodies.push_back(body.name);
    ids[body.name] = body.id;
  }
  manifest.trackers.push_back(tracker);
  manifest.extra["motive"] = {{"file", csv_file.filename().string()}, {"take", take.info}, {"rigid_body_ids", ids}};

  ImportSummary summary;
  summary.session = out;
  summary.notes.push_back("marker columns are not imported (rigid bodies only)");
  summary.notes.push_back("stamps count from the take start ('Time (Seconds)'), not from the wall clock");
  PublishSession(out, csv_file, manifest, [&](SessionWriter& writer, const std::filesystem::path&) {
    Progress progress(options.progress, "import", static_cast<int64_t>(take.rigid_bodies.size()), "bodies");
    for (const auto& body : take.rigid_bodies) {
      WriteBodySamples(writer, "motive", MotiveRecords(take, body), options.gap_limit_ns, summary);
      progress.Advance();
    }
  });
  return summary;
}

}  // namespace mocap::import
