// mocaplabel export S... --format bop|coco|segpairs|tum --out DIR: sessions with their label (and
// validation) runs into one training dataset (exporters/export/export.h, docs/export.md).
#include <CLI/CLI.hpp>
#include <cstdio>

#include "cli/commands.h"
#include "cli/parse_args.h"
#include "cli/progress_flag.h"
#include "core/check.h"
#include "exporters/export/export.h"

namespace mocap::cli {
namespace {

namespace fs = std::filesystem;
using exporters::ExportOptions;

void PrintHuman(const exporters::ExportResult& r) {
  if (r.up_to_date) {
    std::printf("%s is up to date (same inputs, unchanged, and the same options): nothing written\n", r.out_dir.string().c_str());
    return;
  }
  const exporters::SelectionSummary& s = r.selection;
  std::printf("exported %lld of %lld frames, %lld of %lld labels as %s into %s (%.2f s)\n",
              static_cast<long long>(s.frames_kept), static_cast<long long>(s.frames_in),
              static_cast<long long>(r.written.annotations), static_cast<long long>(s.instances_in),
              r.written.format.c_str(), r.out_dir.string().c_str(), r.seconds);
  std::printf("splits:");
  for (const auto& [split, n] : s.frames_per_split) std::printf("  %s=%lld", split.c_str(), static_cast<long long>(n));
  std::printf("\nlabels per object:");
  for (const auto& [name, n] : s.instances_per_object) std::printf("  %s=%lld", name.c_str(), static_cast<long long>(n));
  std::printf("\n");
  for (const auto& [why, n] : s.frames_removed) std::printf("  frames left out: %lld (%s)\n", static_cast<long long>(n), why.c_str());
  for (const auto& [why, n] : s.instances_removed) std::printf("  labels left out: %lld (%s)\n", static_cast<long long>(n), why.c_str());
  for (const std::string& note : r.written.notes) std::printf("  note: %s\n", note.c_str());
}

void AddFilterFlags(CLI::App& app, exporters::ExportFilterOptions& f, bool& keep_frames) {
  app.add_option("--verdicts", f.verdicts, "validator verdicts kept: accept, suspect, reject, unchecked")
      ->delimiter(',')->check(CLI::IsMember({"accept", "suspect", "reject", "unchecked"}))->capture_default_str();
  app.add_option("--drop-flags", f.drop_flags, "label flags that leave a label out (all, none, or a list)")
      ->delimiter(',')->capture_default_str();
  app.add_flag("--keep-frames-with-bad-labels", keep_frames,
               "leave out only a bad label, not its frame (the frame then shows an object without its label)");
  app.add_option("--min-visib", f.min_visib_fract, "labels with a smaller visible fraction are left out")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  app.add_option("--min-motion-mm", f.min_motion_mm, "keep a frame only after this much motion (mm)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--min-motion-deg", f.min_motion_deg, "keep a frame only after this much rotation (deg)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--every-nth", f.every_nth, "keep every Nth frame of a scene")->check(CLI::Range(1, 1000000));
}

void AddSplitFlags(CLI::App& app, exporters::ExportSplitOptions& s, std::string& by, std::vector<double>& fractions) {
  app.add_option("--split", by, "split by time blocks, by session, or none (all frames in train)")
      ->check(CLI::IsMember({"time", "session", "none"}))->capture_default_str();
  app.add_option("--split-fractions", fractions, "train,val,test fractions of the frames")
      ->delimiter(',')->expected(3)->check(CLI::Range(0.0, 1.0));
  app.add_option("--block-s", s.block_s, "time split: block length (s)")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--guard-s", s.guard_s, "time split: gap between splits (s)")->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--seed", s.seed, "split seed")->capture_default_str();
}

}  // namespace

int RunExport(int argc, char** argv) {
  CLI::App app{"Export labelled sessions as a training dataset: BOP, COCO (with poses), segmentation pairs or TUM",
               "mocaplabel export"};
  std::vector<std::string> sessions, labels, validations;
  std::string format, out, split_by = "time";
  std::vector<double> fractions;
  ExportOptions options;
  bool keep_frames = false, no_validation = false, no_depth = false, no_masks = false, no_models = false, json = false;
  app.add_option("sessions", sessions, "session folders")->required();
  app.add_option("--format", format, "bop, coco, segpairs or tum")->required()
      ->check(CLI::IsMember({"bop", "coco", "segpairs", "tum"}));
  app.add_option("--out", out, "dataset folder")->required();
  app.add_option("--labels", labels, "label run of each session, in order (default: SESSION/labels)");
  app.add_option("--validation", validations, "validation run of each session, in order (default: SESSION/validation)");
  app.add_flag("--no-validation", no_validation, "ignore validation runs: every label counts as unchecked");
  AddFilterFlags(app, options.filters, keep_frames);
  AddSplitFlags(app, options.splits, split_by, fractions);
  app.add_flag("--no-depth", no_depth, "BOP, TUM: no depth images");
  app.add_flag("--no-masks", no_masks, "BOP: no mask/ and mask_visib/ images");
  app.add_flag("--no-models", no_models, "BOP: no models/");
  app.add_flag("!--no-coco-ignore", options.coco.write_ignore,
               "COCO: no `ignore` key (detectron2 refuses annotations with a true one)");
  app.add_flag("--keep-invisible", options.coco.keep_invisible, "COCO: keep instances with no visible pixel");
  app.add_flag("!--no-ignore-left-out", options.segpairs.ignore_left_out,
               "segpairs: pixels of left-out labels become background instead of the ignore value");
  app.add_flag("--jpeg-to-png", options.tum.jpeg_to_png, "TUM: re-encode JPEG colour as PNG (TUM's tools expect PNG)");
  app.add_flag("--camera-frame-when-untracked", options.tum.camera_frame_when_untracked,
               "TUM: an untracked camera gives object trajectories in the camera frame instead of an error");
  app.add_option("--threads", options.threads, "worker threads (0: one per core)")->check(CLI::Range(0, 256));
  app.add_flag("--json", json, "print one JSON summary on stdout");
  ProgressFlags progress_flags;
  AddProgressFlags(app, progress_flags);
  app.callback([&] {  // runs inside parse, so a mismatch is a usage error like any other
    if (!labels.empty() && labels.size() != sessions.size())
      throw CLI::ValidationError("--labels", Str("given ", labels.size(), " time(s) for ", sessions.size(), " sessions (once per session, in order)"));
    if (!validations.empty() && validations.size() != sessions.size())
      throw CLI::ValidationError("--validation", Str("given ", validations.size(), " time(s) for ", sessions.size(), " sessions (once per session, in order)"));
  });
  MOCAP_PARSE(app, argc, argv);
  const std::unique_ptr<ProgressSink> progress = ApplyProgressFlags(progress_flags);
  std::vector<exporters::ExportInput> inputs;
  for (size_t i = 0; i < sessions.size(); ++i)
    inputs.push_back({sessions[i], labels.empty() ? "" : labels[i], validations.empty() ? "" : validations[i], no_validation});
  options.format = exporters::ExportFormatFromName(format);
  if (options.filters.drop_flags == std::vector<std::string>{"none"}) options.filters.drop_flags.clear();
  options.filters.drop_frame_with_bad_label = !keep_frames;
  options.splits.by = split_by == "none" ? exporters::SplitBy::kNone
                      : split_by == "session" ? exporters::SplitBy::kSession : exporters::SplitBy::kTime;
  if (!fractions.empty()) options.splits.train = fractions[0], options.splits.val = fractions[1], options.splits.test = fractions[2];
  options.bop.write_depth = options.tum.write_depth = !no_depth, options.bop.write_masks = !no_masks, options.bop.write_models = !no_models;
  const exporters::ExportResult result = exporters::RunExport(inputs, options, out, CommandLine(argc, argv), progress.get());
  if (json) std::printf("%s\n", result.ToJson().dump().c_str());
  else PrintHuman(result);
  return 0;
}

}  // namespace mocap::cli
