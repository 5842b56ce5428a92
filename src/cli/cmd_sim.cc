// mocaplabel sim meshes|check|record: the simulated rig's object library, scenarios and recordings
// (docs/simulation.md).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <nlohmann/json.hpp>

#include "capture/kinect/fakenect_frame_tap.h"
#include "cli/parse_args.h"
#include "cli/commands.h"
#include "cli/progress_flag.h"
#include "cli/scenario_yaml.h"
#include "core/check.h"
#include "pipeline/object_library.h"
#include "pipeline/record_stage.h"
#include "sim/mesh_generator.h"
#include "sim/record/sim_recorder.h"
#include "sim/truth.h"

namespace mocap::cli {
namespace {

int RunSimMeshes(const std::string& out_dir, bool json) {
  std::vector<std::string> written = sim::WriteMeshLibrary(out_dir);
  written.push_back(pipeline::WriteBuiltInObjectLibrary(out_dir).string());
  if (json) {
    std::printf("%s\n", nlohmann::json{{"written", written}}.dump().c_str());
  } else {
    for (const std::string& path : written) std::printf("wrote %s\n", path.c_str());
  }
  return 0;
}

int RunSimCheck(const std::string& scenario_path, const std::string& objects_path, bool print_yaml, bool json) {
  const sim::Scenario scenario = scenario_path.empty() ? sim::DefaultScenario() : LoadScenarioYaml(scenario_path);
  const sim::SimObjects library =
      objects_path.empty() ? sim::DefaultSimObjects() : pipeline::SimObjectsOf(pipeline::ReadObjectLibrary(objects_path));
  scenario.check(library, scenario_path.empty() ? "default scenario" : scenario_path);
  if (print_yaml) {
    std::printf("%s", EncodeScenarioYaml(scenario).c_str());
    return 0;
  }
  const sim::SceneMotion motion(scenario);
  const std::vector<sim::BodyStream> streams = sim::SimulateTrackerStreams(motion, library);
  nlohmann::json bodies = nlohmann::json::array();
  for (const sim::BodyStream& stream : streams)
    bodies.push_back({{"body", stream.body}, {"samples", stream.samples.size()}, {"valid_fraction", stream.valid_fraction()}});
  const nlohmann::json summary{{"name", scenario.options.name},
                               {"frames", scenario.options.frame_count},
                               {"duration_s", scenario.options.duration_s()},
                               {"sensor", std::string(sim::ToString(scenario.options.sensor))},
                               {"objects", scenario.objects.size()},
                               {"occluders", scenario.occluders.size()},
                               {"errors_injected", scenario.options.errors.any()},
                               {"tracker_bodies", bodies}};
  if (json) {
    std::printf("%s\n", summary.dump().c_str());
    return 0;
  }
  std::printf("scenario '%s': %d frames (%.1f s) with a %s, %zu objects, %zu occluders%s\n", scenario.options.name.c_str(),
              scenario.options.frame_count, scenario.options.duration_s(), std::string(sim::ToString(scenario.options.sensor)).c_str(),
              scenario.objects.size(), scenario.occluders.size(), scenario.options.errors.any() ? ", calibration errors injected" : "");
  for (const sim::BodyStream& stream : streams)
    std::printf("  %-14s %5zu tracker samples, %5.1f %% with a pose\n", stream.body.c_str(), stream.samples.size(), 100 * stream.valid_fraction());
  return 0;
}

struct RecordFlags {
  ProgressFlags progress;
  std::string scenario, objects, out, platform = "auto";
  int threads = 0;
  bool fakenect = false;
};

int RunSimRecord(const RecordFlags& flags, bool json) {
  const sim::Scenario scenario = flags.scenario.empty() ? sim::DefaultScenario() : LoadScenarioYaml(flags.scenario);
  // Without --objects the built-in library's meshes are generated into the session (an empty folder).
  std::optional<pipeline::ObjectLibrary> library;
  if (!flags.objects.empty()) library = pipeline::ReadObjectLibrary(flags.objects);
  sim::RecordOptions options;
  options.out_dir = flags.out;
  options.threads = flags.threads;
  std::unique_ptr<capture::FakenectFrameTap> fakenect;
  if (flags.fakenect) fakenect = std::make_unique<capture::FakenectFrameTap>(std::filesystem::path(flags.out) / "fakenect");
  options.frame_tap = fakenect.get();
  options.context.platform = EglPlatformFromString(flags.platform);
  const std::unique_ptr<ProgressSink> progress = ApplyProgressFlags(flags.progress);
  options.progress = progress.get();
  const pipeline::SimRecordResult recorded = pipeline::RecordSimulatedSession(scenario, library ? &*library : nullptr, options);
  const sim::RecordResult& r = recorded.record;
  const nlohmann::json summary{{"session", r.session_dir.string()},   {"frames", r.frames},
                               {"tracker_samples", r.tracker_samples}, {"invalid_depth_fraction", r.invalid_depth_fraction},
                               {"seconds", r.seconds},                {"rig", recorded.rig_file.string()},
                               {"objects", recorded.objects_file.string()},  {"truth", r.truth_dir.string()},
                               {"fakenect", fakenect ? fakenect->dir().string() : std::string()}, {"errors_injected", scenario.options.errors.any()}};
  if (json) {
    std::printf("%s\n", summary.dump().c_str());
    return 0;
  }
  std::printf("recorded %d frames and %lld tracker samples of '%s' in %.1f s into %s (%.1f %% of pixels without depth)\n",
              r.frames, static_cast<long long>(r.tracker_samples), scenario.options.name.c_str(), r.seconds,
              r.session_dir.string().c_str(), 100 * r.invalid_depth_fraction);
  std::printf("label it with: mocaplabel label %s --rig %s --objects %s\n", r.session_dir.string().c_str(),
              recorded.rig_file.string().c_str(), recorded.objects_file.string().c_str());
  return 0;
}

}  // namespace

int RunSim(int argc, char** argv) {
  CLI::App app{"Simulated rig: object meshes and scenarios", "mocaplabel sim"};
  app.require_subcommand(1);
  bool json = false;
  app.add_flag("--json", json, "print one JSON document");
  std::string out_dir = "meshes";
  CLI::App* meshes = app.add_subcommand("meshes", "generate the procedural meshes and objects.yaml");
  meshes->add_option("--out", out_dir, "output folder")->capture_default_str();
  meshes->add_flag("--json", json, "print one JSON document");
  std::string scenario_path, objects_path;
  bool print_yaml = false;
  CLI::App* check = app.add_subcommand("check", "check a scenario and summarise its tracker streams");
  check->add_option("--scenario", scenario_path, "scenario YAML (default: the embedded default scenario)");
  check->add_option("--objects", objects_path, "objects.yaml (default: the built-in library of meshes/)");
  check->add_flag("--print-yaml", print_yaml, "print the scenario as YAML instead (scenarios/default.yaml is this for the default)");
  check->add_flag("--json", json, "print one JSON document");
  RecordFlags record_flags;
  CLI::App* record = app.add_subcommand("record", "simulate a scenario into a session with its truth");
  record->add_option("--scenario", record_flags.scenario, "scenario YAML (default: the embedded default scenario)");
  record->add_option("--objects", record_flags.objects, "objects.yaml (default: the built-in library, meshes generated into the session)");
  record->add_option("--out", record_flags.out, "session folder to create")->required();
  record->add_option("--threads", record_flags.threads, "render threads, each with its own EGL context (0: one per core)");
  record->add_option("--platform", record_flags.platform, "EGL platform: auto, surfaceless or device");
  record->add_flag("--fakenect", record_flags.fakenect, "also write the Kinect v1 frames as a fakenect recording (S/fakenect)");
  record->add_flag("--json", json, "print one JSON document");
  AddProgressFlags(*record, record_flags.progress);
  MOCAP_PARSE(app, argc, argv);
  if (meshes->parsed()) return RunSimMeshes(out_dir, json);
  if (record->parsed()) return RunSimRecord(record_flags, json);
  return RunSimCheck(scenario_path, objects_path, print_yaml, json);
}

}  // namespace mocap::cli
