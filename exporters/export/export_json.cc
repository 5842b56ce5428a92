// The export's options and summary as JSON: run.json `options` and export.json (docs/export.md "Summary").
#include "core/check.h"
#include "exporters/export/export.h"

namespace mocap::exporters {
namespace {

const char* SplitByName(SplitBy by) {
  switch (by) {
    case SplitBy::kNone: return "none";
    case SplitBy::kSession: return "session";
    case SplitBy::kTime: return "time";
  }
  return "?";
}

nlohmann::json SelectionJson(const SelectionSummary& s) {
  return {{"frames_in", s.frames_in},           {"frames_kept", s.frames_kept},
          {"instances_in", s.instances_in},     {"instances_kept", s.instances_kept},
          {"frames_removed", s.frames_removed}, {"instances_removed", s.instances_removed},
          {"frames_per_split", s.frames_per_split}, {"instances_per_object", s.instances_per_object}};
}

nlohmann::json WrittenJson(const WriteSummary& w) {
  return {{"format", w.format},
          {"images", w.images},
          {"annotations", w.annotations},
          {"files", w.files},
          {"images_per_split", w.images_per_split},
          {"annotations_per_split", w.annotations_per_split},
          {"notes", w.notes}};
}

}  // namespace

std::string_view ToString(ExportFormat format) {
  switch (format) {
    case ExportFormat::kBop: return "bop";
    case ExportFormat::kCoco: return "coco";
    case ExportFormat::kSegpairs: return "segpairs";
    case ExportFormat::kTum: return "tum";
  }
  return "?";
}

ExportFormat ExportFormatFromName(const std::string& name) {
  for (ExportFormat f : {ExportFormat::kBop, ExportFormat::kCoco, ExportFormat::kSegpairs, ExportFormat::kTum})
    if (ToString(f) == name) return f;
  throw InputError("--format", Str("unknown format '", name, "' (bop, coco, segpairs, tum)"));
}

nlohmann::json ToJson(const ExportOptions& o) {
  const ExportFilterOptions& f = o.filters;
  const ExportSplitOptions& s = o.splits;
  return {{"format", ToString(o.format)},
          {"filters", {{"verdicts", f.verdicts}, {"drop_flags", f.drop_flags},
                       {"drop_frame_with_bad_label", f.drop_frame_with_bad_label},
                       {"min_visib_fract", f.min_visib_fract}, {"min_motion_mm", f.min_motion_mm},
                       {"min_motion_deg", f.min_motion_deg}, {"every_nth", f.every_nth}}},
          {"splits", {{"by", SplitByName(s.by)}, {"train", s.train}, {"val", s.val}, {"test", s.test},
                      {"block_s", s.block_s}, {"guard_s", s.guard_s}, {"seed", s.seed}, {"none_split", s.none_split}}},
          {"bop", {{"write_depth", o.bop.write_depth}, {"write_masks", o.bop.write_masks},
                   {"write_models", o.bop.write_models}, {"converted_depth_scale_mm", o.bop.converted_depth_scale_mm}}},
          {"coco", {{"ignore_below_visib_fract", o.coco.ignore_below_visib_fract}, {"write_ignore", o.coco.write_ignore},
                    {"keep_invisible", o.coco.keep_invisible}}},
          {"segpairs", {{"ignore_left_out", o.segpairs.ignore_left_out}}},
          {"tum", {{"write_depth", o.tum.write_depth}, {"write_objects", o.tum.write_objects},
                   {"jpeg_to_png", o.tum.jpeg_to_png}, {"camera_frame_when_untracked", o.tum.camera_frame_when_untracked}}}};
}

nlohmann::json ExportResult::ToJson() const {
  return {{"complete", true},
          {"out", out_dir.string()},
          {"up_to_date", up_to_date},
          {"seconds", seconds},
          {"selection", SelectionJson(selection)},
          {"written", WrittenJson(written)}};
}

ExportResult ExportResultFromJson(const nlohmann::json& j, const std::filesystem::path& out_dir) {
  ExportResult r;
  r.out_dir = out_dir;
  try {
    const nlohmann::json& s = j.at("selection");
    r.selection.frames_in = s.at("frames_in"), r.selection.frames_kept = s.at("frames_kept");
    r.selection.instances_in = s.at("instances_in"), r.selection.instances_kept = s.at("instances_kept");
    r.selection.frames_removed = s.at("frames_removed").get<std::map<std::string, int64_t>>();
    r.selection.instances_removed = s.at("instances_removed").get<std::map<std::string, int64_t>>();
    r.selection.frames_per_split = s.at("frames_per_split").get<std::map<std::string, int64_t>>();
    r.selection.instances_per_object = s.at("instances_per_object").get<std::map<std::string, int64_t>>();
    const nlohmann::json& w = j.at("written");
    r.written.format = w.at("format"), r.written.images = w.at("images"), r.written.annotations = w.at("annotations");
    r.written.files = w.at("files");
    r.written.images_per_split = w.at("images_per_split").get<std::map<std::string, int64_t>>();
    r.written.annotations_per_split = w.at("annotations_per_split").get<std::map<std::string, int64_t>>();
    r.written.notes = w.at("notes").get<std::vector<std::string>>();
    r.seconds = j.at("seconds");
  } catch (const nlohmann::json::exception& e) {
    throw InputError((out_dir / "export.json").string(), Str("not an export summary: ", e.what()));
  }
  return r;
}

}  // namespace mocap::exporters
