// mocaplabel sim meshes|check: the simulated rig's object library and scenarios (docs/simulation.md).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/scenario_yaml.h"
#include "core/check.h"
#include "sim/mesh_generator.h"
#include "sim/truth.h"

namespace mocap::cli {
namespace {

int RunSimMeshes(const std::string& out_dir, bool json) {
  const std::vector<std::string> written = sim::WriteMeshLibrary(out_dir);
  if (json) {
    std::printf("%s\n", nlohmann::json{{"written", written}}.dump().c_str());
  } else {
    for (const std::string& path : written) std::printf("wrote %s\n", path.c_str());
  }
  return 0;
}

int RunSimCheck(const std::string& scenario_path, const std::string& objects_path, bool print_yaml, bool json) {
  const sim::Scenario scenario = scenario_path.empty() ? sim::DefaultScenario() : LoadScenarioYaml(scenario_path);
  const sim::ObjectLibrary library = objects_path.empty() ? sim::DefaultObjectLibrary() : LoadSimObjectsYaml(objects_path);
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
  CLI11_PARSE(app, argc, argv);
  if (meshes->parsed()) return RunSimMeshes(out_dir, json);
  return RunSimCheck(scenario_path, objects_path, print_yaml, json);
}

}  // namespace mocap::cli
