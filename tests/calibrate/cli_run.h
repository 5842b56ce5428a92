#pragma once
// Running the mocaplabel binary from the calibration tests, as a user runs it, and reading what it says.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "core/rigid3.h"

namespace mocap::test {

/// Runs MOCAPLABEL_EXE with `args`; `out` gets stdout and stderr together. Returns the exit code.
int Mocaplabel(const std::vector<std::string>& args, std::string* out);
/// The last line of `output` that starts with '{', parsed (null when none).
nlohmann::json LastJson(const std::string& output);
std::string ReadText(const std::filesystem::path& file);
/// A pose as the CLI prints it: {"translation_m": [...], "rotation_wxyz": [...]}.
Rigid3d PoseOf(const nlohmann::json& j);
/// A pose as truth/calibration.json holds it: {"q_wxyz": [...], "t_m": [...]}.
Rigid3d TruthPoseOf(const nlohmann::json& j);

}  // namespace mocap::test
