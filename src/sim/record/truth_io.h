#pragma once
// Files of a simulated recording besides the session itself: the truth (JSON). The calibration handed
// to the labeller (rig.yaml, objects.yaml) is written by the pipeline's writers (pipeline/record_stage.h).
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "sim/sim_objects.h"
#include "sim/truth.h"

namespace mocap::sim {

nlohmann::json ToJson(const RigCalibration& calibration);
nlohmann::json ToJson(const CalibrationErrors& errors);
/// truth/instance/<frame>.png: the true instance image of simulated frame `frame`.
std::filesystem::path TruthInstancePng(const std::filesystem::path& truth_dir, int64_t frame);
/// One line of truth/poses.jsonl.
nlohmann::json FrameTruthJson(const FrameTruth& frame);

/// Writes `json` (pretty) or raises InputError naming the file.
void WriteJsonFile(const std::filesystem::path& path, const nlohmann::json& json);

}  // namespace mocap::sim
