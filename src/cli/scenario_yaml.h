#pragma once
// Simulation scenarios (docs/simulation.md) from YAML onto the sim structs: the only place scenario
// files are read, with the pipeline's strict YAML helpers (pipeline/yaml_read.h). Errors name the file,
// the line and the key; an unknown key is an error with "did you mean".
#include <filesystem>
#include <string>

#include "sim/scenario.h"

namespace mocap::cli {

/// Parses a scenario; every field is optional and falls back to DefaultScenario(), except that a
/// listed `objects` / `occluders` replaces the default list. Unknown keys are errors (typos). Throws
/// InputError with file:line. Does not check the scenario against a library (Scenario::check does).
sim::Scenario ParseScenarioYaml(const std::string& text, const std::string& file_name);
sim::Scenario LoadScenarioYaml(const std::filesystem::path& path);

/// The YAML text of a scenario (what scenarios/default.yaml holds for DefaultScenario()).
std::string EncodeScenarioYaml(const sim::Scenario& scenario);

}  // namespace mocap::cli
