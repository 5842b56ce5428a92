#pragma once
// Simulated sessions for relabel tests, recorded through the mocaplabel binary as a user records them:
// the default scenario cut to a few frames, with some of its objects left out so that sessions differ
// in the objects they hold; one shared rig and object library beside them.
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mocap::testing {

struct RelabelSessions {
  std::filesystem::path dir, rig, objects;
  std::vector<std::filesystem::path> sessions;
};

/// Records one session per entry of `left_out` (the scenario objects it leaves out) under `name`, each
/// `frames` frames, and copies the rig, object library and meshes of the first beside them.
RelabelSessions MakeRelabelSessions(const std::string& name, const std::vector<std::vector<std::string>>& left_out,
                                    int frames);

/// Runs mocaplabel with `args` (and `env` added); the exit code, `output` filled with stdout + stderr.
int Mocaplabel(const std::vector<std::string>& args, std::string* output = nullptr,
               const std::map<std::string, std::string>& env = {});
/// The last line of `output` that parses as a JSON object.
nlohmann::json LastJson(const std::string& output);

/// Every file under `dir` (relative path -> bytes), but those named in `skip` (files whose content
/// carries times or the command: run.json, the run manifests, export.json, report.html).
std::map<std::string, std::string> TreeFiles(const std::filesystem::path& dir);

/// Moves `object`'s mount in the object library file by `dz_m` along the body's z axis.
void ShiftMount(const std::filesystem::path& objects_yaml, const std::string& object, double dz_m);

}  // namespace mocap::testing
