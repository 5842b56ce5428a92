// mocaplabel demo [--out DIR] [--json] [--scenario F] [--frames N]: the whole tool on the simulated rig
// (docs/demo.md), as the list of pipeline stages assembled here: record, capture (through the capture
// daemon), label, validate (SegICP), score against the truth, contact sheet.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli/parse_args.h"
#include "cli/commands.h"
#include "exporters/export/export.h"
#include "cli/progress_flag.h"
#include "cli/scenario_yaml.h"
#include "core/check.h"
#include "pipeline/demo.h"
#include "pipeline/label_stage.h"
#include "pipeline/record_stage.h"
#include "pipeline/validate_stage.h"

namespace mocap::cli {
namespace {

double Number(const nlohmann::json& j, const char* key) { return j.value(key, 0.0); }

void PrintHuman(const pipeline::DemoResult& r) {
  const nlohmann::json& s = r.summary;
  std::printf("demo: scenario '%s', %lld frames labelled (%lld dropped), %lld object records (%lld without a pose)\n",
              s["scenario"].get<std::string>().c_str(), s.value("frames", 0LL), s.value("dropped_frames", 0LL),
              s.value("records", 0LL), s.value("records_without_pose", 0LL));
  std::printf("  mask IoU (label vs true visible mask): mean %.4f, 5th percentile %.4f\n", Number(s, "mask_iou_mean"),
              Number(s, "mask_iou_p5"));
  std::printf("  pose error vs truth: median %.3f mm / %.3f deg, 95th percentile %.3f mm / %.3f deg\n",
              Number(s, "pose_err_mm_median"), Number(s, "pose_err_deg_median"), Number(s, "pose_err_mm_p95"),
              Number(s, "pose_err_deg_p95"));
  std::printf("  flagged frames: %lld\n", s["flagged_frames"].is_number() ? s["flagged_frames"].get<long long>() : 0LL);
  if (s["validate_frame_stride"].is_number()) {
    const nlohmann::json& rate = s["segicp_success_rate"];
    std::printf("  validation (SegICP, %lld frames, one in %d): success rate %s, verdicts", s["validated_frames"].get<long long>(),
                s["validate_frame_stride"].get<int>(),
                rate.is_number() ? Str(std::lround(1000 * rate.get<double>()) / 10.0, " %").c_str() : "n/a (nothing checkable)");
    for (const auto& [verdict, count] : s["verdicts"].items()) std::printf(" %s %lld", verdict.c_str(), count.get<long long>());
    std::printf("\n");
  }
  if (const nlohmann::json& e = s["export"]; e.is_object()) {
    std::printf("  dataset (%s): %lld frames, %lld labels;", e["written"]["format"].get<std::string>().c_str(),
                e["written"]["images"].get<long long>(), e["written"]["annotations"].get<long long>());
    for (const auto& [split, n] : e["selection"]["frames_per_split"].items()) std::printf(" %s %lld", split.c_str(), n.get<long long>());
    std::printf("\n");
  }
  std::printf("  seconds:");
  for (const auto& [stage, seconds] : r.seconds_per_stage) std::printf(" %s %.1f", stage.c_str(), seconds);
  std::printf("\n");
  for (const auto& note : s["notes"]) std::printf("  note: %s\n", note.get<std::string>().c_str());
  for (const auto& [name, path] : s["outputs"].items()) std::printf("  %-17s %s\n", name.c_str(), path.get<std::string>().c_str());
}

/// The demo's dataset: BOP (what pose-estimation training reads), split by time with the defaults.
exporters::ExportOptions DemoExportOptions() {
  exporters::ExportOptions options;
  options.format = exporters::ExportFormat::kBop;
  return options;
}

}  // namespace

int RunDemo(int argc, char** argv) {
  CLI::App app{"The whole tool on the simulated rig: simulate, record through the capture daemon, label, validate, score", "mocaplabel demo"};
  pipeline::DemoOptions options;
  std::string out_dir = "demo-out/sim", scenario_path, platform = "auto";
  bool json = false;
  app.add_option("--out", out_dir, "output folder (replaced when it holds an earlier demo)")->capture_default_str();
  app.add_option("--scenario", scenario_path, "scenario YAML (default: the embedded default scenario)");
  app.add_option("--frames", options.frames, "simulate only the first N frames (0: all of the scenario's)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--validate-every", options.validate_frame_stride, "validate one frame in K (1: every frame)")
      ->capture_default_str()->check(CLI::Range(1, 1'000'000));
  app.add_option("--threads", options.threads, "worker threads, each with its own EGL context (0: one per core)")
      ->check(CLI::Range(0, 256));
  app.add_option("--platform", platform, "EGL platform: auto, surfaceless or device");
  app.add_flag("--json", json, "print one JSON document on stdout");
  ProgressFlags progress_flags;
  AddProgressFlags(app, progress_flags);
  MOCAP_PARSE(app, argc, argv);
  const std::unique_ptr<ProgressSink> progress = ApplyProgressFlags(progress_flags);
  options.progress = progress.get();
  options.out_dir = out_dir;
  options.context.platform = EglPlatformFromString(platform);
  const sim::Scenario scenario =
      pipeline::DemoScenario(scenario_path.empty() ? sim::DefaultScenario() : LoadScenarioYaml(scenario_path), options);
  const std::vector<pipeline::Stage> stages = {pipeline::MakeRecordStage(scenario),
                                               pipeline::MakeCaptureStage(),
                                               pipeline::MakeDemoLabelStage(),
                                               pipeline::MakeValidateStage(options.validate_frame_stride, {}),
                                               pipeline::MakeScoreStage(),
                                               pipeline::MakeContactSheetStage(),
                                               exporters::MakeExportStage(DemoExportOptions())};
  const pipeline::DemoResult result = pipeline::RunDemo(options, stages, scenario.options.frame_count, scenario.options.name,
                                                        CommandLine(argc, argv));
  if (json) std::printf("%s\n", result.summary.dump().c_str());
  else PrintHuman(result);
  return 0;
}

}  // namespace mocap::cli
