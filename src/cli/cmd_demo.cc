// mocaplabel demo [--out DIR] [--json] [--scenario F] [--frames N]: the whole tool on the simulated rig
// (docs/demo.md): simulate, record through the capture daemon, label, validate (SegICP), score against
// the truth, contact sheet.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/demo_capture.h"
#include "cli/scenario_yaml.h"
#include "core/check.h"
#include "sim/demo/demo_pipeline.h"
#include "sim/record/truth_io.h"

namespace mocap::cli {
namespace {

void PrintHuman(const sim::DemoResult& r) {
  const sim::DemoContext& c = r.context;
  const sim::LabelScores& s = c.scores;
  std::printf("demo: scenario '%s', %lld frames labelled (%lld dropped), %lld object records (%lld without a pose)\n",
              c.scenario.options.name.c_str(), static_cast<long long>(s.frames),
              static_cast<long long>(c.scenario.options.frame_count - s.frames), static_cast<long long>(s.records),
              static_cast<long long>(s.records_without_pose));
  std::printf("  mask IoU (label vs true visible mask): mean %.4f, 5th percentile %.4f\n", s.mask_iou_mean, s.mask_iou_p5);
  std::printf("  pose error vs truth: median %.3f mm / %.3f deg, 95th percentile %.3f mm / %.3f deg\n",
              s.pose_err_mm_median, s.pose_err_deg_median, s.pose_err_mm_p95, s.pose_err_deg_p95);
  std::printf("  flagged frames: %lld\n", static_cast<long long>(c.label.frames_flagged));
  if (c.validate_frame_stride > 0) {
    std::printf("  validation (SegICP, %lld frames, one in %d): success rate %s, verdicts", static_cast<long long>(c.validated_frames),
                c.validate_frame_stride,
                c.segicp_success_rate ? Str(std::lround(1000 * *c.segicp_success_rate) / 10.0, " %").c_str() : "n/a (nothing checkable)");
    for (const auto& [verdict, count] : c.verdicts.items()) std::printf(" %s %lld", verdict.c_str(), count.get<long long>());
    std::printf("\n");
  }
  std::printf("  seconds:");
  for (const auto& [stage, seconds] : r.seconds_per_stage) std::printf(" %s %.1f", stage.c_str(), seconds);
  std::printf("\n");
  for (const std::string& note : c.notes) std::printf("  note: %s\n", note.c_str());
  for (const auto& [name, path] : c.outputs) std::printf("  %-13s %s\n", name.c_str(), path.c_str());
}

}  // namespace

int RunDemo(int argc, char** argv) {
  CLI::App app{"The whole tool on the simulated rig: simulate, record through the capture daemon, label, validate, score", "mocaplabel demo"};
  sim::DemoOptions options;
  options.out_dir = "demo-out/sim";
  std::string out_dir = options.out_dir.string(), scenario_path, platform = "auto";
  bool json = false;
  app.add_option("--out", out_dir, "output folder (replaced when it holds an earlier demo)")->capture_default_str();
  app.add_option("--scenario", scenario_path, "scenario YAML (default: the embedded default scenario)");
  app.add_option("--frames", options.frames, "simulate only the first N frames (0: all of the scenario's)");
  app.add_option("--validate-every", options.validate_frame_stride, "validate one frame in K (1: every frame)")
      ->capture_default_str();
  app.add_option("--threads", options.threads, "worker threads, each with its own EGL context (0: one per core)");
  app.add_option("--platform", platform, "EGL platform: auto, surfaceless or device");
  app.add_flag("--json", json, "print one JSON document on stdout");
  CLI11_PARSE(app, argc, argv);
  options.out_dir = out_dir;
  options.context.platform = EglPlatformFromString(platform);
  const sim::Scenario scenario = scenario_path.empty() ? sim::DefaultScenario() : LoadScenarioYaml(scenario_path);
  const sim::DemoResult result = sim::RunDemo(scenario, options, DemoStagesThroughDaemon());
  const nlohmann::json summary = sim::DemoJson(result);
  sim::WriteJsonFile(options.out_dir / "demo.json", summary);
  if (json) std::printf("%s\n", summary.dump().c_str());
  else PrintHuman(result);
  return 0;
}

}  // namespace mocap::cli
