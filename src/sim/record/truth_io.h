#pragma once
// Files of a simulated recording besides the session itself: the truth (JSON) and the calibration
// handed to the labeller (rig and object library YAML, the formats of docs/rig.md and docs/objects.md).
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "sim/object_library.h"
#include "sim/truth.h"

namespace mocap::sim {

nlohmann::json ToJson(const RigCalibration& calibration);
nlohmann::json ToJson(const CalibrationErrors& errors);
/// One line of truth/poses.jsonl.
nlohmann::json FrameTruthJson(const FrameTruth& frame);

/// Rig YAML (docs/rig.md) for `calibration`: camera `camera` on tracker body `camera_body`.
std::string EncodeRigYaml(const std::string& name, const std::string& camera, const std::string& camera_body,
                          const RigCalibration& calibration);

/// `library` with the object mounts of `calibration` (T_objbody_mesh per object name) and mesh paths
/// relative to `yaml_dir` (so the written objects.yaml finds the meshes in `library_dir`).
ObjectLibrary LibraryForLabelling(const ObjectLibrary& library, const RigCalibration& calibration,
                                  const std::filesystem::path& library_dir, const std::filesystem::path& yaml_dir);

/// Writes `json` (pretty) or raises InputError naming the file.
void WriteJsonFile(const std::filesystem::path& path, const nlohmann::json& json);

}  // namespace mocap::sim
