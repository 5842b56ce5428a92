#include "session/stats.h"

#include <algorithm>
#include <cstdio>
#include <set>

#include "core/check.h"

namespace mocap {
namespace fs = std::filesystem;

void SessionStatsOptions::check() const {
  if (gap_limit_ns <= 0) throw InputError("SessionStatsOptions", "gap_limit_ns must be positive");
  interpolation.check();
}

namespace {

/// Precondition: stamps sorted.
StreamTiming TimingOf(const std::vector<int64_t>& stamps, int64_t gap_limit_ns) {
  StreamTiming timing;
  timing.count = static_cast<int64_t>(stamps.size());
  if (stamps.empty()) return timing;
  timing.start_ns = stamps.front();
  timing.end_ns = stamps.back();
  timing.duration_s = static_cast<double>(timing.end_ns - timing.start_ns) * 1e-9;
  if (timing.count > 1 && timing.duration_s > 0.0)
    timing.rate_hz = static_cast<double>(timing.count - 1) / timing.duration_s;
  for (size_t i = 1; i < stamps.size(); ++i) {
    if (stamps[i] == stamps[i - 1]) ++timing.duplicates;
    if (stamps[i] - stamps[i - 1] > gap_limit_ns) timing.gaps.push_back({stamps[i - 1], stamps[i]});
  }
  return timing;
}

int64_t SkippedFrameNumbers(int64_t previous, int64_t current) {
  return current > previous + 1 ? current - previous - 1 : 0;
}

CameraStats CameraStatsOf(const SessionReader& reader, const CameraStreamInfo& camera,
                          const SessionStatsOptions& options, std::vector<std::string>* missing_files) {
  CameraStats stats;
  stats.name = camera.name;
  stats.frames_subset = camera.frames_subset;
  const auto frames = reader.frames(camera.name);
  stats.records = static_cast<int64_t>(frames.size());
  const bool has_body = !camera.camera_body.empty() && reader.TrackerOfBody(camera.camera_body).has_value();
  if (has_body) stats.frames_with_pose = 0;
  std::vector<int64_t> stamps;
  for (size_t i = 0; i < frames.size(); ++i) {
    const CameraFrameEntry& entry = frames[i];
    const CameraFrameRecord& record = entry.record;
    stamps.push_back(record.stamp_ns);
    if (i > 0) {
      if (!camera.frames_subset) stats.dropped_frames += SkippedFrameNumbers(frames[i - 1].record.frame, record.frame);
      stats.stamps_backwards += record.stamp_ns < frames[i - 1].record.stamp_ns;
    }
    stats.color_listed += record.has_color();
    stats.color_present += entry.color_present;
    stats.depth_listed += record.has_depth();
    stats.depth_present += entry.depth_present;
    const fs::path camera_dir = fs::path("cameras") / camera.name;
    if (record.has_color() && !entry.color_present) missing_files->push_back((camera_dir / record.color_file).string());
    if (record.has_depth() && !entry.depth_present) missing_files->push_back((camera_dir / record.depth_file).string());
    if (!entry.color_present || !entry.depth_present) continue;
    ++stats.frames;
    if (!has_body) continue;
    const InterpolatedPose pose = reader.CameraPoseAtFrame(camera.name, static_cast<int64_t>(i), options.interpolation);
    if (pose.ok()) {
      ++*stats.frames_with_pose;
    } else {
      ++stats.pose_failures[std::string(ToString(pose.failure))];
    }
  }
  std::sort(stamps.begin(), stamps.end());
  stats.timing = TimingOf(stamps, options.gap_limit_ns);
  return stats;
}

BodyStats BodyStatsOf(const SessionReader& reader, const std::string& tracker, const std::string& body,
                      const SessionStatsOptions& options) {
  BodyStats stats;
  stats.tracker = tracker;
  stats.body = body;
  for (auto status : {PoseStatus::kValid, PoseStatus::kMissing, PoseStatus::kDisabled, PoseStatus::kOutOfVolume,
                      PoseStatus::kPartiallyInVolume})
    stats.status_counts[std::string(ToString(status))] = 0;
  const std::vector<TrackerRecord> records = reader.BodyRecords(tracker, body);  // sorted by stamp
  stats.samples = static_cast<int64_t>(records.size());
  std::vector<int64_t> stamps;
  std::optional<TimeSpan> dropout;
  for (size_t i = 0; i < records.size(); ++i) {
    const TrackerRecord& record = records[i];
    stamps.push_back(record.stamp_ns);
    ++stats.status_counts[std::string(ToString(record.status))];
    stats.rms_error_max_m = std::max(stats.rms_error_max_m, record.rms_error_m);
    if (i > 0) stats.dropped_frames += SkippedFrameNumbers(records[i - 1].device_frame, record.device_frame);
    if (!HasPose(record.status)) {
      if (!dropout) dropout = TimeSpan{record.stamp_ns, record.stamp_ns};
      dropout->end_ns = record.stamp_ns;
    } else if (dropout) {
      stats.dropouts.push_back(*dropout);
      dropout.reset();
    }
  }
  if (dropout) stats.dropouts.push_back(*dropout);
  stats.timing = TimingOf(stamps, options.gap_limit_ns);
  return stats;
}

nlohmann::json SpansJson(const std::vector<TimeSpan>& spans) {
  nlohmann::json json = nlohmann::json::array();
  for (const auto& span : spans)
    json.push_back({{"start_ns", span.start_ns}, {"end_ns", span.end_ns},
                    {"duration_s", static_cast<double>(span.end_ns - span.start_ns) * 1e-9}});
  return json;
}

nlohmann::json TimingJson(const StreamTiming& timing) {
  return {{"start_ns", timing.start_ns}, {"end_ns", timing.end_ns}, {"duration_s", timing.duration_s},
          {"rate_hz", timing.rate_hz},   {"duplicates", timing.duplicates}, {"gaps", SpansJson(timing.gaps)}};
}

nlohmann::json OptionalJson(const std::optional<int64_t>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

}  // namespace

SessionStats ComputeSessionStats(const SessionReader& reader, const SessionStatsOptions& options) {
  options.check();
  const SessionManifest& manifest = reader.manifest();
  SessionStats stats;
  stats.dir = reader.dir().string();
  stats.complete = reader.complete();
  stats.format_version = manifest.format_version;
  stats.software_version = manifest.software_version;
  stats.created_utc = manifest.created_utc;
  stats.source = manifest.source;
  stats.gap_limit_ns = options.gap_limit_ns;
  for (const auto& camera : manifest.cameras) {
    stats.cameras.push_back(CameraStatsOf(reader, camera, options, &stats.missing_files));
    const CameraStats& camera_stats = stats.cameras.back();
    stats.frames += camera_stats.frames;
    if (camera_stats.frames_with_pose)
      stats.frames_with_pose = stats.frames_with_pose.value_or(0) + *camera_stats.frames_with_pose;
  }
  for (const auto& tracker : manifest.trackers)
    for (const auto& body : tracker.bodies) stats.bodies.push_back(BodyStatsOf(reader, tracker.name, body, options));
  stats.clock_fits = manifest.clock_fits;
  for (const auto& event : reader.events()) ++stats.event_counts[event.kind];
  stats.streams = reader.diagnostics();
  return stats;
}

nlohmann::json ToJson(const SessionStats& stats) {
  nlohmann::json json = {{"session", stats.dir},
                         {"complete", stats.complete},
                         {"format_version", stats.format_version},
                         {"software_version", stats.software_version},
                         {"created_utc", stats.created_utc},
                         {"source", stats.source},
                         {"gap_limit_s", static_cast<double>(stats.gap_limit_ns) * 1e-9},
                         {"frames", stats.frames},
                         {"frames_with_pose", OptionalJson(stats.frames_with_pose)},
                         {"missing_files", stats.missing_files.size()},
                         {"missing_file_list", stats.missing_files},
                         {"cameras", nlohmann::json::object()},
                         {"tracker_bodies", nlohmann::json::object()},
                         {"clock_fits", nlohmann::json::object()},
                         {"events", stats.event_counts},
                         {"streams", nlohmann::json::array()}};
  for (const auto& camera : stats.cameras) {
    json["cameras"][camera.name] = {
        {"records", camera.records},       {"color_listed", camera.color_listed},
        {"color_present", camera.color_present}, {"depth_listed", camera.depth_listed},
        {"depth_present", camera.depth_present}, {"frames", camera.frames},
        {"frames_with_pose", OptionalJson(camera.frames_with_pose)}, {"pose_failures", camera.pose_failures},
        {"dropped_frames", camera.dropped_frames}, {"frames_subset", camera.frames_subset},
        {"stamps_backwards", camera.stamps_backwards},
        {"timing", TimingJson(camera.timing)}};
  }
  std::map<std::string, int> body_names;
  for (const auto& body : stats.bodies) ++body_names[body.body];
  for (const auto& body : stats.bodies) {
    const std::string key = body_names[body.body] > 1 ? body.tracker + "/" + body.body : body.body;
    nlohmann::json entry = TimingJson(body.timing);
    entry.update({{"tracker", body.tracker},
                  {"samples", body.samples},
                  {"status_counts", body.status_counts},
                  {"dropouts", SpansJson(body.dropouts)},
                  {"dropped_frames", body.dropped_frames},
                  {"rms_error_max_m", body.rms_error_max_m}});
    json["tracker_bodies"][key] = entry;
  }
  for (const auto& [device, fit] : stats.clock_fits) json["clock_fits"][device] = ToJson(fit);
  for (const auto& stream : stats.streams)
    json["streams"].push_back({{"file", stream.file}, {"records", stream.records}, {"torn_tail", stream.torn_tail},
                               {"corrupt_lines", stream.corrupt_lines}});
  return json;
}

}  // namespace mocap
