// mocaplabel import tum|plus|motive|bop: existing recordings into sessions (docs/importers.md).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli/parse_args.h"
#include "cli/commands.h"
#include "cli/progress_flag.h"
#include "core/check.h"
#include "pipeline/object_library.h"
#include "session/import/bop_import.h"
#include "session/import/text_parse.h"
#include "session/import/tracker_import.h"
#include "session/import/tum_import.h"

namespace mocap::cli {
namespace {

// "--intrinsics": a preset name (fr1, fr2, fr3, ros) or "fx,fy,cx,cy" for a 640x480 undistorted camera.
void ParseIntrinsics(const std::string& text, import::TumImportOptions& options) {
  if (text.find(',') == std::string::npos) {
    options.preset = import::TumPresetFromName(text);
    return;
  }
  const auto fields = import::SplitFields(text, ',');
  if (fields.size() != 4) throw InputError("--intrinsics", "expected fx,fy,cx,cy (pixels) or fr1|fr2|fr3|ros");
  PinholeCamera camera;
  camera.width = 640;
  camera.height = 480;
  const import::NumberRange cx_range{0, static_cast<double>(camera.width), "px"};
  const import::NumberRange cy_range{0, static_cast<double>(camera.height), "px"};
  camera.fx = import::CheckInRange(import::ParseDouble(fields[0], "--intrinsics fx"), import::kFocalLengthRangePx, "--intrinsics fx");
  camera.fy = import::CheckInRange(import::ParseDouble(fields[1], "--intrinsics fy"), import::kFocalLengthRangePx, "--intrinsics fy");
  camera.cx = import::CheckInRange(import::ParseDouble(fields[2], "--intrinsics cx"), cx_range, "--intrinsics cx");
  camera.cy = import::CheckInRange(import::ParseDouble(fields[3], "--intrinsics cy"), cy_range, "--intrinsics cy");
  options.camera = camera;
}

nlohmann::json ToJson(const import::ImportSummary& summary) {
  nlohmann::json bodies = nlohmann::json::object();
  for (const auto& [name, body] : summary.bodies) {
    nlohmann::json gaps = nlohmann::json::array();
    for (const auto& gap : body.gaps) gaps.push_back({{"start_ns", gap.start_ns}, {"end_ns", gap.end_ns}});
    bodies[name] = {{"samples", body.samples}, {"status_counts", body.status_counts},
                    {"duplicates", body.duplicate_stamps}, {"gaps", gaps}};
  }
  return {{"session", summary.session.string()},
          {"camera_records", summary.camera_records},
          {"frames", summary.frames_with_color_and_depth},
          {"frames_color_only", summary.frames_color_only},
          {"missing_files", summary.missing_files},
          {"tracker_samples", summary.tracker_samples},
          {"tracker_bodies", bodies},
          {"notes", summary.notes}};
}

void Print(const import::ImportSummary& summary, bool json) {
  if (json) {
    std::printf("%s\n", ToJson(summary).dump(2).c_str());
    return;
  }
  std::printf("imported into %s: %lld camera records (%lld with colour and depth, %lld colour only), "
              "%lld missing files, %lld tracker samples\n",
              summary.session.c_str(), static_cast<long long>(summary.camera_records),
              static_cast<long long>(summary.frames_with_color_and_depth), static_cast<long long>(summary.frames_color_only),
              static_cast<long long>(summary.missing_files), static_cast<long long>(summary.tracker_samples));
  for (const auto& [name, body] : summary.bodies)
    std::printf("  %s: %lld samples, %zu gaps, %lld duplicated stamps\n", name.c_str(), static_cast<long long>(body.samples),
                body.gaps.size(), static_cast<long long>(body.duplicate_stamps));
  for (const auto& note : summary.notes) std::printf("  note: %s\n", note.c_str());
}

int64_t Nanoseconds(double seconds, const char* flag) {
  return std::llround(import::CheckInRange(seconds, import::kTimeSpanRangeS, flag) * 1e9);
}

}  // namespace

int RunImport(int argc, char** argv) {
  CLI::App app{"Import an existing recording into a new session folder", "mocaplabel import"};
  app.require_subcommand(1);
  bool json = false;
  std::string source, out, intrinsics, models;
  double gap_limit_s = 0.5, max_difference_s = 0.02, rate_hz = 30.0;
  double depth_factor = import::kTumDepthUnitsPerMetre;
  app.add_flag("--json", json, "print one JSON document");

  auto* tum = app.add_subcommand("tum", "TUM RGB-D sequence folder, or a groundtruth.txt-format trajectory");
  tum->add_option("source", source, "sequence folder (rgb.txt, depth.txt, groundtruth.txt) or trajectory file")->required();
  tum->add_option("--intrinsics", intrinsics, "fr1|fr2|fr3|ros or fx,fy,cx,cy (default: from the bag name)");
  tum->add_option("--max-difference", max_difference_s, "rgb/depth association window (s)")->capture_default_str();
  tum->add_option("--depth-factor", depth_factor, "depth PNG values per metre")->capture_default_str();
  auto* plus = app.add_subcommand("plus", "PLUS sequence metafile (.mha) tracker log");
  plus->add_option("file", source, ".mha / .igs.mha file")->required();
  auto* motive = app.add_subcommand("motive", "OptiTrack Motive CSV export");
  motive->add_option("file", source, "CSV file")->required();
  auto* bop = app.add_subcommand("bop", "BOP scene folder with its models");
  bop->add_option("scene", source, "scene folder (scene_camera.json, scene_gt.json, rgb/)")->required();
  bop->add_option("--models", models, "models folder (models_info.json, obj_NNNNNN.ply)")->required();
  bop->add_option("--rate", rate_hz, "synthetic frame rate turning im_id into time (Hz)")->capture_default_str();
  ProgressFlags progress_flags;
  for (auto* sub : {tum, plus, motive, bop}) {
    AddProgressFlags(*sub, progress_flags);
    sub->add_option("--out", out, "new session folder")->required();
    sub->add_flag("--json", json, "print one JSON document");
    if (sub != bop) sub->add_option("--gap-limit", gap_limit_s, "log spans between samples longer than this (s)")->capture_default_str();
  }
  MOCAP_PARSE(app, argc, argv);

  const std::unique_ptr<ProgressSink> progress = ApplyProgressFlags(progress_flags);
  import::ImportSummary summary;
  if (tum->parsed()) {
    import::TumImportOptions options;
    options.software_version = MOCAP_VERSION;
    options.progress = progress.get();
    options.gap_limit_ns = Nanoseconds(gap_limit_s, "--gap-limit");
    options.association.max_difference_ns = Nanoseconds(max_difference_s, "--max-difference");
    options.depth_units_per_metre = import::CheckInRange(depth_factor, import::kDepthUnitsPerMetreRange, "--depth-factor");
    if (!intrinsics.empty()) ParseIntrinsics(intrinsics, options);
    summary = import::ImportTum(source, out, options);
  } else if (plus->parsed() || motive->parsed()) {
    import::TrackerImportOptions options;
    options.software_version = MOCAP_VERSION;
    options.progress = progress.get();
    options.gap_limit_ns = Nanoseconds(gap_limit_s, "--gap-limit");
    summary = plus->parsed() ? import::ImportPlus(source, out, options) : import::ImportMotive(source, out, options);
  } else {
    import::BopImportOptions options;
    options.software_version = MOCAP_VERSION;
    options.progress = progress.get();
    options.frame_rate_hz = import::CheckInRange(rate_hz, import::kBopFrameRateRangeHz, "--rate");
    options.write_objects = pipeline::WriteBopObjects;
    summary = import::ImportBop(source, models, out, options);
  }
  Print(summary, json);
  return 0;
}

}  // namespace mocap::cli
