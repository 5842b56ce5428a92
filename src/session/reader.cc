#include "session/reader.h"

#include <algorithm>

#include "core/check.h"
#include "session/image_io.h"
#include "session/record_file.h"

namespace mocap {
namespace fs = std::filesystem;

namespace {

/// A session closed cleanly has no torn tail and as many records as its manifest counted at closing: a
/// file with fewer was cut or damaged after recording, and reading on would lose poses silently.
void CheckStreamIsWhole(const SessionManifest& manifest, const fs::path& path, const fs::path& relative,
                        const RecordFileContents& contents, const SessionReaderOptions& options) {
  if (!manifest.complete || options.skip_corrupt_records) return;
  const auto expected = manifest.stream_records.find(relative.generic_string());
  const auto read = static_cast<int64_t>(contents.records.size());
  if (expected != manifest.stream_records.end() && read < expected->second)
    throw InputError(path.string(), Str("holds ", read, " whole records, but the session was closed with ", expected->second,
                                        ": the file was cut or damaged after recording (restore it from a copy)"));
  if (contents.torn_tail)
    throw InputError(path.string(), Str("its last line (after record ", read, ") is cut short, but the session was "
                                        "closed cleanly: the file was damaged after recording (restore it from a copy)"));
}

template <typename Record, typename Parse>
std::vector<Record> ReadStream(const fs::path& dir, const SessionManifest& manifest, const fs::path& relative,
                               const SessionReaderOptions& options, Parse parse,
                               std::vector<StreamDiagnostics>* diagnostics) {
  const fs::path path = dir / relative;
  const RecordFileContents contents = ReadRecordFile(path, options.skip_corrupt_records);
  std::vector<Record> records;
  records.reserve(contents.records.size());
  for (const auto& line : contents.records) records.push_back(parse(line.json, Str(path.string(), ":", line.line)));
  CheckStreamIsWhole(manifest, path, relative, contents, options);
  diagnostics->push_back({relative.string(), static_cast<int64_t>(records.size()), contents.torn_tail,
                          contents.corrupt_lines});
  return records;
}

}  // namespace

SessionReader SessionReader::Open(const fs::path& dir, const SessionReaderOptions& options) {
  options.check();
  SessionReader reader;
  reader.dir_ = dir;
  reader.manifest_ = LoadManifest(dir);
  for (const auto& camera : reader.manifest_.cameras) {
    const fs::path camera_dir = dir / "cameras" / camera.name;
    auto records = ReadStream<CameraFrameRecord>(dir, reader.manifest_, CameraStreamFile(camera.name), options,
                                                 CameraFrameRecordFromJson, &reader.diagnostics_);
    CameraStream& stream = reader.cameras_[camera.name];
    stream.entries.reserve(records.size());
    for (auto& record : records) {
      CameraFrameEntry entry;
      entry.color_present = record.has_color() && fs::exists(camera_dir / record.color_file);
      entry.depth_present = record.has_depth() && fs::exists(camera_dir / record.depth_file);
      entry.record = std::move(record);
      stream.entries.push_back(std::move(entry));
    }
  }
  for (const auto& tracker : reader.manifest_.trackers) {
    const fs::path file = TrackerStreamFile(tracker.name);
    TrackerStream& stream = reader.trackers_[tracker.name];
    stream.records = ReadStream<TrackerRecord>(dir, reader.manifest_, file, options, TrackerRecordFromJson, &reader.diagnostics_);
    for (size_t i = 0; i < stream.records.size(); ++i) {
      const TrackerRecord& record = stream.records[i];
      if (std::find(tracker.bodies.begin(), tracker.bodies.end(), record.body) == tracker.bodies.end())
        throw InputError(Str((dir / file).string(), ": record ", i + 1),
                         Str("body '", record.body, "' is not among the manifest's bodies of tracker '", tracker.name, "'"));
      stream.by_body[record.body].push_back(i);
    }
    for (auto& [body, indices] : stream.by_body) {
      std::stable_sort(indices.begin(), indices.end(),
                       [&](size_t a, size_t b) { return stream.records[a].stamp_ns < stream.records[b].stamp_ns; });
      auto& poses = stream.poses_by_body[body];
      poses.reserve(indices.size());
      for (size_t i : indices) {
        const TrackerRecord& record = stream.records[i];
        poses.push_back({record.stamp_ns, record.status, record.T_frame_body});
      }
    }
  }
  reader.events_ = ReadStream<EventRecord>(dir, reader.manifest_, "events.jsonl", options, EventRecordFromJson, &reader.diagnostics_);
  return reader;
}

const SessionReader::CameraStream& SessionReader::camera_stream(const std::string& camera) const {
  const auto it = cameras_.find(camera);
  if (it == cameras_.end()) throw InputError(dir_.string(), Str("the session has no camera '", camera, "'"));
  return it->second;
}

const SessionReader::TrackerStream& SessionReader::tracker_stream(const std::string& tracker) const {
  const auto it = trackers_.find(tracker);
  if (it == trackers_.end()) throw InputError(dir_.string(), Str("the session has no tracker '", tracker, "'"));
  return it->second;
}

int64_t SessionReader::frame_count(const std::string& camera) const {
  return static_cast<int64_t>(camera_stream(camera).entries.size());
}

const CameraFrameEntry& SessionReader::frame(const std::string& camera, int64_t index) const {
  const auto& entries = camera_stream(camera).entries;
  MOCAP_CHECK(index >= 0 && index < static_cast<int64_t>(entries.size()), "frame index ", index, " out of range [0, ",
              entries.size(), ") of camera ", camera);
  return entries[static_cast<size_t>(index)];
}

std::span<const CameraFrameEntry> SessionReader::frames(const std::string& camera) const {
  return camera_stream(camera).entries;
}

fs::path SessionReader::ColorPath(const std::string& camera, int64_t index) const {
  const auto& record = frame(camera, index).record;
  return record.has_color() ? dir_ / "cameras" / camera / record.color_file : fs::path();
}

fs::path SessionReader::DepthPath(const std::string& camera, int64_t index) const {
  const auto& record = frame(camera, index).record;
  return record.has_depth() ? dir_ / "cameras" / camera / record.depth_file : fs::path();
}

cv::Mat SessionReader::LoadColor(const std::string& camera, int64_t index) const {
  const fs::path path = ColorPath(camera, index);
  if (path.empty()) throw InputError(Str(camera, " frame ", index), "this record has no colour image");
  return ReadColor(path);
}

DepthImage SessionReader::LoadDepth(const std::string& camera, int64_t index) const {
  const fs::path path = DepthPath(camera, index);
  if (path.empty()) throw InputError(Str(camera, " frame ", index), "this record has no depth image");
  return ReadDepth(path, manifest_.FindCamera(camera)->depth_unit_m);
}

std::span<const TrackerRecord> SessionReader::tracker_records(const std::string& tracker) const {
  return tracker_stream(tracker).records;
}

std::vector<TrackerRecord> SessionReader::BodyRecords(const std::string& tracker, const std::string& body) const {
  const TrackerStream& stream = tracker_stream(tracker);
  std::vector<TrackerRecord> records;
  const auto it = stream.by_body.find(body);
  if (it == stream.by_body.end()) return records;
  records.reserve(it->second.size());
  for (size_t i : it->second) records.push_back(stream.records[i]);
  return records;
}

const std::vector<PoseSample>& SessionReader::PoseSamples(const std::string& tracker, const std::string& body) const {
  static const std::vector<PoseSample> kNone;
  const TrackerStream& stream = tracker_stream(tracker);
  const auto it = stream.poses_by_body.find(body);
  return it == stream.poses_by_body.end() ? kNone : it->second;
}

std::optional<std::string> SessionReader::TrackerOfBody(const std::string& body) const {
  for (const auto& tracker : manifest_.trackers)
    if (std::find(tracker.bodies.begin(), tracker.bodies.end(), body) != tracker.bodies.end()) return tracker.name;
  return std::nullopt;
}

SamplesAround SessionReader::SamplesAroundFrame(const std::string& camera, int64_t index, const std::string& tracker,
                                                const std::string& body) const {
  const int64_t stamp_ns = frame(camera, index).record.stamp_ns;
  const TrackerStream& stream = tracker_stream(tracker);
  SamplesAround around;
  const auto it = stream.by_body.find(body);
  if (it == stream.by_body.end()) return around;
  const auto& indices = it->second;
  const auto after = std::upper_bound(indices.begin(), indices.end(), stamp_ns,
                                      [&](int64_t t, size_t i) { return t < stream.records[i].stamp_ns; });
  if (after != indices.end()) around.after = stream.records[*after];
  if (after != indices.begin()) around.before = stream.records[*std::prev(after)];
  return around;
}

InterpolatedPose SessionReader::CameraPoseAtFrame(const std::string& camera, int64_t index,
                                                  const InterpolationOptions& options) const {
  const CameraStreamInfo* info = manifest_.FindCamera(camera);
  if (!info) throw InputError(dir_.string(), Str("the session has no camera '", camera, "'"));
  const auto tracker = info->camera_body.empty() ? std::nullopt : TrackerOfBody(info->camera_body);
  if (!tracker) {
    InterpolatedPose none;
    none.failure = InterpolationFailure::kEmptyStream;
    return none;
  }
  const std::vector<PoseSample>& samples = PoseSamples(*tracker, info->camera_body);
  InterpolatedPose result = InterpolatePose(samples, frame(camera, index).record.stamp_ns, options);
  if (result.ok()) result.pose = *result.pose * info->T_body_camera;
  return result;
}

}  // namespace mocap
