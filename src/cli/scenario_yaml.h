#pragma once
// Simulation scenarios (docs/simulation.md) and the simulator's view of an object library
// (docs/objects.md) from YAML onto the sim structs: the only place these files are read. Errors name
// the file and the line of the offending node.
#include <filesystem>
#include <string>

#include "sim/object_library.h"
#include "sim/scenario.h"

namespace mocap::cli {

/// Parses a scenario; every field is optional and falls back to DefaultScenario(), except that a
/// listed `objects` / `occluders` replaces the default list. Unknown keys are errors (typos). Throws
/// InputError with file:line. Does not check the scenario against a library (Scenario::check does).
sim::Scenario ParseScenarioYaml(const std::string& text, const std::string& file_name);
sim::Scenario LoadScenarioYaml(const std::filesystem::path& path);

/// The YAML text of a scenario (what scenarios/default.yaml holds for DefaultScenario()).
std::string EncodeScenarioYaml(const sim::Scenario& scenario);

/// objects.yaml with the simulator's fields (markers_m, marker_normal, reflectivity, ...).
sim::ObjectLibrary ParseSimObjectsYaml(const std::string& text, const std::string& file_name);
sim::ObjectLibrary LoadSimObjectsYaml(const std::filesystem::path& path);

}  // namespace mocap::cli
