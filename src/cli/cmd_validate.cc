// mocaplabel validate S --labels L [--masks DIR] [--skip-objects A,B | --objects-only A,B] [--out DIR]: the SegICP check of every label against the
// measured depth (src/validate/session_check.h), with validation.jsonl, validation.json and report.html.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli/parse_args.h"
#include "cli/commands.h"
#include "cli/progress_flag.h"
#include "core/check.h"
#include "pipeline/validate_stage.h"
#include "pipeline/json_read.h"
#include "pipeline/validation_run.h"

namespace mocap::cli {
namespace {

namespace fs = std::filesystem;

void PrintHuman(const ValidationSummary& s, const fs::path& out) {
  if (s.records_checked == 0) {
    // No rate or median to report: they would read as measurements (0 %, 0.00 mm).
    std::printf("checked 0 of %lld label records: nothing was checked, because %s\n",
                static_cast<long long>(s.records), s.nothing_checked_why.c_str());
    std::printf("%.2f s; report in %s\n", s.seconds, (out / "report.html").string().c_str());
    return;
  }
  std::printf("checked %lld of %lld label records (%lld without a pose); SegICP success %.1f %%\n",
              static_cast<long long>(s.records_checked), static_cast<long long>(s.records),
              static_cast<long long>(s.records_without_pose), 100 * s.segicp_success_rate);
  std::printf("verdicts:");
  for (const auto& [v, n] : s.verdicts) std::printf("  %s=%lld", v.c_str(), static_cast<long long>(n));
  std::printf("\nposition error median %.2f mm (p95 %.2f), rotation median %.2f deg (p95 %.2f)\n",
              s.position_error_mm.median, s.position_error_mm.p95, s.rotation_angle_error_deg.median,
              s.rotation_angle_error_deg.p95);
  if (s.session_wide) {
    if (!s.session_wide->ran) std::printf("session-wide check not run: %s\n", s.session_wide->why_not.c_str());
    for (const std::string& f : s.session_wide->findings) std::printf("session-wide: %s\n", f.c_str());
    if (s.session_wide->records_flagged > 0)
      std::printf("session-wide: %lld accepted records made suspect (camera_mount_off, object_mount_off)\n",
                  static_cast<long long>(s.session_wide->records_flagged));
  }
  if (s.has_segmentation)
    std::printf("masks: IoU median %.3f (std %.3f), precision %.3f, recall %.3f\n", s.iou.median, s.iou.std,
                s.precision.median, s.recall.median);
  std::printf("%.2f s; report in %s\n", s.seconds, (out / "report.html").string().c_str());
}

}  // namespace

int RunValidate(int argc, char** argv) {
  CLI::App app{"Check every label against the measured depth with SegICP; verdicts and a report", "mocaplabel validate"};
  std::string session_dir, labels_dir, objects_file, masks_dir, out_dir, mask_values = "object", crops = "surface",
                                                                         seed = "label", platform = "auto";
  pipeline::ValidateRunRequest request;
  SessionCheckOptions& options = request.check;
  bool json = false;
  app.add_option("session", session_dir, "session folder")->required();
  app.add_option("--labels", labels_dir, "label run folder (default: SESSION/labels)");
  app.add_option("--objects", objects_file, "object library YAML (default: the session's objects.yaml)");
  app.add_option("--masks", masks_dir, "user masks: DIR/<camera>/NNNNNN.png (or DIR/NNNNNN.png), 0 = background");
  app.add_option("--mask-values", mask_values, "what user mask pixels hold: object (id) or instance")
      ->check(CLI::IsMember({"object", "instance"}));
  app.add_option("--out", out_dir, "output folder (default: SESSION/validation)");
  app.add_option("--crops", crops, "model crops: surface (CPU z-buffer) or renderer (EGL)")
      ->check(CLI::IsMember({"surface", "renderer"}));
  app.add_option("--seed", seed, "acquisition seed: label (hypotheses about the label) or view-sphere (the paper)")
      ->check(CLI::IsMember({"label", "view-sphere"}));
  bool per_frame = false;
  CLI::Option* track = app.add_flag("--track", options.track,
                                    "sequence mode (the default): a Kalman tracker per object instance over its frames");
  app.add_flag("--per-frame", per_frame, "check every record on its own (an acquisition per record; slower)")->excludes(track);
  app.add_option("--threads", options.threads, "worker threads (0: one per core)")->check(CLI::Range(0, 256));
  app.add_option("--platform", platform, "EGL platform for --crops renderer: auto, surfaceless or device");
  CLI::Option* skip = app.add_option("--skip-objects", request.skip_object_names, "leave out these objects (names, comma-separated)")
                         ->delimiter(',');
  app.add_option("--objects-only", request.only_object_names, "check only these objects (names, comma-separated)")
      ->delimiter(',')
      ->excludes(skip);
  bool no_session_wide = false;
  app.add_flag("--no-session-wide", no_session_wide,
               "leave out the session-wide step (a camera mount the records together show off flags that camera's labels)");
  app.add_flag("--json", json, "print validation.json on stdout");
  ProgressFlags progress_flags;
  AddProgressFlags(app, progress_flags);
  MOCAP_PARSE(app, argc, argv);
  const std::unique_ptr<ProgressSink> progress = ApplyProgressFlags(progress_flags);
  request.progress = progress.get();

  options.labels_dir = labels_dir.empty() ? fs::path(session_dir) / "labels" : fs::path(labels_dir);
  request.session_dir = session_dir;
  request.labels_dir = options.labels_dir;
  request.objects_file = objects_file;
  request.command = CommandLine(argc, argv);
  options.masks_dir = masks_dir;
  options.track = !per_frame;
  options.mask_values = mask_values == "object" ? MaskValues::kObjectId : MaskValues::kInstanceId;
  options.crops = crops == "renderer" ? CropBackend::kRenderer : CropBackend::kSurface;
  options.validate.check_seed = seed == "label" ? AcquisitionSeed::kLabel : AcquisitionSeed::kViewSphere;
  options.context.platform = EglPlatformFromString(platform);
  const fs::path out = out_dir.empty() ? fs::path(session_dir) / "validation" : fs::path(out_dir);
  request.out_dir = out;
  request.session_wide.enabled = !no_session_wide;
  const SessionValidation result = pipeline::RunValidate(request);
  if (json)
    std::printf("%s\n", pipeline::ReadJsonFile(pipeline::ValidationRunLayout{out}.summary_json()).dump().c_str());
  else
    PrintHuman(result.summary, out);
  return 0;
}

}  // namespace mocap::cli
