#pragma once
// objects.yaml (docs/objects.md) onto the validator's object list: the labeller's fields plus each
// object's declared symmetry, so that `mocaplabel validate` compares SegICP estimates with labels modulo
// it (a funnel's continuous symmetry, a table's half turn).
#include <filesystem>
#include <vector>

#include "validate/session_check.h"

namespace mocap::cli {

/// The objects of an object library (LoadObjectsYaml's checks) with their symmetries. The validator
/// compares modulo one symmetry per object: the first continuous one, else the first discrete one (a
/// discrete one's angle_deg must divide 360). Throws InputError with file:line on a malformed entry.
std::vector<ValidationObject> LoadValidationObjects(const std::filesystem::path& path);

}  // namespace mocap::cli
