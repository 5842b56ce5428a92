#include "session/import/tum_import.h"

#include <algorithm>

#include "core/check.h"
#include "session/import/image_check.h"
#include "session/writer.h"

namespace mocap::import {
namespace {

constexpr const char* kCamera = "rgbd";
constexpr const char* kTracker = "groundtruth";
constexpr const char* kBody = "camera";

struct PlannedFrame {
  int64_t stamp_ns = 0;
  std::string source_id;
  std::filesystem::path color, depth;  // empty: no such image in this record
};

std::string PresetName(TumCameraPreset preset) {
  switch (preset) {
    case TumCameraPreset::kFreiburg1: return "fr1";
    case TumCameraPreset::kFreiburg2: return "fr2";
    case TumCameraPreset::kFreiburg3: return "fr3";
    case TumCameraPreset::kRosDefault: return "ros";
  }
  return "ros";
}

// The colour camera and a note saying where it came from.
std::pair<PinholeCamera, std::string> ChooseCamera(const TumSequence& seq, const TumImportOptions& options) {
  if (options.camera) return {*options.camera, "intrinsics given by the user"};
  if (options.preset)
    return {TumCamera(*options.preset), "intrinsics: TUM preset " + PresetName(*options.preset) + " (chosen by the user)"};
  if (auto preset = TumPresetFromBagName(seq.rgb.bag_name))
    return {TumCamera(*preset), Str("intrinsics: TUM published ", PresetName(*preset), " colour calibration (from '",
                                    seq.rgb.bag_name, "')")};
  return {TumCamera(TumCameraPreset::kRosDefault),
          "intrinsics: ROS default 525/525/319.5/239.5 (the sequence does not name its sensor; pass --intrinsics)"};
}

// One record per rgb entry (with its associated depth), plus depth-only records, in time order.
std::vector<PlannedFrame> PlanFrames(const TumSequence& seq) {
  std::vector<PlannedFrame> frames;
  std::vector<bool> depth_used(seq.depth.entries.size(), false);
  std::vector<long> depth_of_rgb(seq.rgb.entries.size(), -1);
  for (const auto& pair : seq.rgb_depth) {
    depth_of_rgb[pair.first] = static_cast<long>(pair.second);
    depth_used[pair.second] = true;
  }
  for (size_t i = 0; i < seq.rgb.entries.size(); ++i) {
    const auto& rgb = seq.rgb.entries[i];
    PlannedFrame f{rgb.stamp_ns, rgb.stamp_text, seq.dir / rgb.relative_path, {}};
    if (depth_of_rgb[i] >= 0) f.depth = seq.dir / seq.depth.entries[static_cast<size_t>(depth_of_rgb[i])].relative_path;
    frames.push_back(f);
  }
  for (size_t j = 0; j < seq.depth.entries.size(); ++j)
    if (!depth_used[j])
      frames.push_back({seq.depth.entries[j].stamp_ns, seq.depth.entries[j].stamp_text, {}, seq.dir / seq.depth.entries[j].relative_path});
  std::stable_sort(frames.begin(), frames.end(), [](const auto& a, const auto& b) { return a.stamp_ns < b.stamp_ns; });
  // Every image is checked before the session is created, so a bad one leaves no partial session.
  for (const auto& f : frames) {
    if (!f.color.empty()) CheckImportableImage(f.color, false);
    if (!f.depth.empty()) CheckImportableImage(f.depth, true);
  }
  return frames;
}

std::vector<TrackerRecord> GroundTruthRecords(const TumGroundTruth& gt) {
  std::vector<TrackerRecord> records;
  records.reserve(gt.samples.size());
  for (size_t i = 0; i < gt.samples.size(); ++i) {
    TrackerRecord r;
    r.body = kBody;
    r.status = PoseStatus::kValid;
    r.device_frame = static_cast<int64_t>(i);  // TUM has no tracker frame numbers: the sample's index
    r.stamp_ns = gt.samples[i].stamp_ns;
    r.T_frame_body = gt.samples[i].pose;
    records.push_back(r);
  }
  return records;
}

SessionManifest BaseManifest(const std::filesystem::path& source, const TumImportOptions& options) {
  SessionManifest manifest;
  manifest.software_version = options.software_version;
  manifest.source = "import tum " + std::filesystem::absolute(source).lexically_normal().string();
  manifest.trackers.push_back({kTracker, "tum_mocap", "", "tracker", {kBody}});
  return manifest;
}

void WriteFrames(SessionWriter& writer, const std::vector<PlannedFrame>& frames, ProgressSink* sink, ImportSummary& summary) {
  Progress progress(sink, "import", static_cast<int64_t>(frames.size()), "frames");
  for (size_t i = 0; i < frames.size(); ++i, progress.Advance()) {
    const auto& f = frames[i];
    CameraFrameRecord record;
    record.frame = static_cast<int64_t>(i);
    record.stamp_ns = f.stamp_ns;
    record.source_id = f.source_id;
    writer.AddCameraFrameFiles(kCamera, record, f.color, f.depth);
    const bool color = !f.color.empty() && std::filesystem::is_regular_file(f.color);
    const bool depth = !f.depth.empty() && std::filesystem::is_regular_file(f.depth);
    summary.missing_files += (!f.color.empty() && !color) + (!f.depth.empty() && !depth);
    summary.frames_with_color_and_depth += color && depth;
    summary.frames_color_only += color && !depth;
  }
  summary.camera_records = static_cast<int64_t>(frames.size());
}

ImportSummary ImportTrajectory(const std::filesystem::path& file, const std::filesystem::path& out,
                               const TumImportOptions& options) {
  const TumGroundTruth gt = ReadTumGroundTruth(file);
  SessionManifest manifest = BaseManifest(file, options);
  manifest.extra["tum"] = {{"groundtruth", file.filename().string()}, {"poses", gt.samples.size()}};
  ImportSummary summary;
  summary.session = out;
  PublishSession(out, file, manifest, [&](SessionWriter& writer, const std::filesystem::path&) {
    WriteBodySamples(writer, kTracker, GroundTruthRecords(gt), options.gap_limit_ns, summary);
  });
  summary.notes.push_back("trajectory only: no camera stream");
  return summary;
}

}  // namespace

void TumImportOptions::check() const {
  association.check();
  if (camera) camera->check();
  if (gap_limit_ns <= 0) throw InputError("TumImportOptions", "gap_limit_ns must be positive");
  CheckInRange(depth_units_per_metre, kDepthUnitsPerMetreRange, "TumImportOptions::depth_units_per_metre");
}

ImportSummary ImportTum(const std::filesystem::path& source, const std::filesystem::path& out,
                        const TumImportOptions& options) {
  options.check();
  CheckOutputFolder(out);
  if (std::filesystem::is_regular_file(source)) return ImportTrajectory(source, out, options);
  const TumSequence seq = ReadTumSequence(source, options.association);
  const auto [camera, camera_note] = ChooseCamera(seq, options);

  SessionManifest manifest = BaseManifest(source, options);
  CameraStreamInfo info;
  info.name = kCamera;
  const auto sensor = TumPresetFromBagName(seq.rgb.bag_name);
  info.model = "tum_" + (sensor ? PresetName(*sensor) : std::string("unknown"));
  info.serial = seq.rgb.bag_name;
  info.color_camera = camera;
  info.depth_camera = camera;  // TUM depth is registered to the colour camera by the driver
  info.depth_registered_to_color = true;
  info.depth_unit_m = 1.0 / options.depth_units_per_metre;
  info.camera_body = kBody;  // the ground truth is the colour optical centre itself
  manifest.cameras.push_back(info);
  nlohmann::json pairs = nlohmann::json::array();
  for (const auto& p : seq.rgb_depth)
    pairs.push_back({seq.rgb.entries[p.first].stamp_text, seq.depth.entries[p.second].stamp_text});
  manifest.extra["tum"] = {{"sequence", seq.rgb.bag_name},
                           {"intrinsics", camera_note},
                           {"depth_units_per_metre", options.depth_units_per_metre},
                           {"association_max_difference_s", static_cast<double>(options.association.max_difference_ns) * 1e-9},
                           {"rgb_depth_pairs", pairs}};

  ImportSummary summary;
  summary.session = out;
  summary.notes.push_back(camera_note);
  if (options.depth_units_per_metre != kTumDepthUnitsPerMetre)
    summary.notes.push_back(Str("depth: ", options.depth_units_per_metre, " units per metre (given by the user; TUM uses ",
                                kTumDepthUnitsPerMetre, ")"));
  for (int line : seq.rgb.header_lines_without_hash)
    summary.notes.push_back(Str(seq.rgb.file.string(), ":", line, ": header line without '#' skipped"));
  for (int line : seq.depth.header_lines_without_hash)
    summary.notes.push_back(Str(seq.depth.file.string(), ":", line, ": header line without '#' skipped"));
  const std::vector<PlannedFrame> frames = PlanFrames(seq);
  PublishSession(out, source, manifest, [&](SessionWriter& writer, const std::filesystem::path&) {
    WriteFrames(writer, frames, options.progress, summary);
    WriteBodySamples(writer, kTracker, GroundTruthRecords(seq.groundtruth), options.gap_limit_ns, summary);
  });
  return summary;
}

}  // namespace mocap::import
