#pragma once
// Rig files (calib/*.yaml, docs/rig.md) onto the labeller's Rig.
#include <filesystem>

#include "label/rig.h"

namespace mocap::cli {

/// Throws InputError with file:line on bad input.
Rig LoadRigYaml(const std::filesystem::path& path);

}  // namespace mocap::cli
