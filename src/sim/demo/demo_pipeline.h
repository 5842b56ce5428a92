#pragma once
// `mocaplabel demo`: the whole tool on the simulated rig, as a list of stages over one shared context
// (docs/demo.md). The default stages are
//   record   simulate the scenario and write the session (sim record; frames go to the session writer
//            directly: the capture daemon stage is to replace this one)
//   label    the labeller, as a library, with the calibration the recording hands it (rig.yaml content)
//   score    labels against the truth (scoring.h)
//   contact_sheet
// A validation stage (SegICP) slots in after `label` and fills `segicp_success_rate` and `verdicts`;
// until one exists they stay unset and the JSON has them as null.
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "label/labeller.h"
#include "sim/demo/label_inputs.h"
#include "sim/demo/scoring.h"
#include "sim/record/sim_recorder.h"

namespace mocap::sim {

struct DemoOptions {
  std::filesystem::path out_dir;  ///< replaced if it holds an earlier demo (demo.json), else must be empty
  int frames = 0;                 ///< 0: the scenario's frame count; else the first N frames
  int threads = 0;                ///< 0: one per core
  RenderContextOptions context;
  void check() const;  ///< throws InputError
};

/// Everything the stages share. A stage reads what earlier stages filled and adds its own part.
struct DemoContext {
  DemoOptions options;
  Scenario scenario;
  ObjectLibrary library;
  RecordResult record;
  LabelSummary label;
  std::filesystem::path labels_dir;
  LabelScores scores;
  std::optional<double> segicp_success_rate;  ///< filled by a validation stage
  nlohmann::json verdicts;                    ///< filled by a validation stage; null until then
  std::map<std::string, std::string> outputs;  ///< name -> path
  std::vector<std::string> notes;              ///< one line each, printed in the summary
};

struct DemoStage {
  std::string name;
  std::function<void(DemoContext&)> run;
};

/// record, label, score, contact_sheet (in that order).
std::vector<DemoStage> DefaultDemoStages();

struct DemoResult {
  DemoContext context;
  std::vector<std::pair<std::string, double>> seconds_per_stage;
};

/// Runs `stages` in order on `scenario` (the built-in object library; meshes generated into the output).
/// Throws InputError from the stage that failed.
DemoResult RunDemo(const Scenario& scenario, const DemoOptions& options, const std::vector<DemoStage>& stages);

/// The fields of `mocaplabel demo --json` (docs/demo.md).
nlohmann::json DemoJson(const DemoResult& result);

/// Labels a simulated recording with `calibration` (true or given) into `labels_dir`: instance images and
/// labels.jsonl only, with the demo's threads and EGL platform.
LabelSummary LabelRecording(const RecordResult& record, const ObjectLibrary& library, const RigCalibration& calibration,
                            const std::filesystem::path& labels_dir, const DemoOptions& options);
/// LabelRecording, then ScoreLabels against the recording's truth, with visible masks from the measured depth.
LabelScores LabelAndScore(const RecordResult& record, const ObjectLibrary& library, const RigCalibration& calibration,
                          const std::filesystem::path& labels_dir, const DemoOptions& options);

}  // namespace mocap::sim
