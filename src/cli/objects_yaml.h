#pragma once
// objects.yaml (docs/objects.md) onto the labeller's object list.
#include <filesystem>
#include <vector>

#include "label/label_objects.h"

namespace mocap::cli {

/// Reads an object library. Mesh paths are resolved against the file's folder. Each object names its
/// tracker body as `tracker_body` (with `T_body_mesh`, identity when absent) or several as
/// `tracker_bodies` (names, mounted at identity: BOP imports). Throws InputError with file:line.
std::vector<LabelObject> LoadObjectsYaml(const std::filesystem::path& path);

}  // namespace mocap::cli
