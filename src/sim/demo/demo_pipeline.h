#pragma once
// `mocaplabel demo`: the whole tool on the simulated rig, as a list of stages over one shared context
// (docs/demo.md). The default stages are
//   record   simulate the scenario and write the simulated session (sim record, with the session writer)
// `mocaplabel demo` inserts a `capture` stage after it (src/cli/demo_capture.h) that plays the simulated
// session through the capture daemon in real time (capture/daemon/rerecord.h); the later stages then
// work on the session the daemon wrote, with the simulated one's truth and calibration files.
//   label    the labeller, as a library, with the calibration the recording hands it (rig.yaml content)
//   validate the SegICP session check of the labels against the measured depth (validate_stage.h)
//   score    labels against the truth (scoring.h)
//   contact_sheet
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
  /// The validate stage checks the frames whose index is a multiple of this (1: every frame). The
  /// default keeps the default demo within its time budget on 2 cores (docs/demo.md).
  int validate_frame_stride = 15;
  RenderContextOptions context;
  void check() const;  ///< throws InputError
};

/// Everything the stages share. A stage reads what earlier stages filled and adds its own part.
struct DemoContext {
  DemoOptions options;
  Scenario scenario;
  ObjectLibrary library;
  RecordResult record;  ///< session_dir: the session the later stages read (the daemon's, after `capture`)
  nlohmann::json capture;  ///< filled by a capture stage (frames, drops, tracker link); null: none ran
  LabelSummary label;
  std::filesystem::path labels_dir;
  LabelScores scores;
  std::optional<double> segicp_success_rate;  ///< filled by the validate stage (unset: nothing checkable)
  nlohmann::json verdicts;                    ///< filled by the validate stage; null until then
  int64_t validated_frames = 0;               ///< frames whose records the validate stage checked
  int validate_frame_stride = 0;              ///< the stride it used; 0: no validate stage ran
  std::map<std::string, std::string> outputs;  ///< name -> path
  std::vector<std::string> notes;              ///< one line each, printed in the summary
};

struct DemoStage {
  std::string name;
  std::function<void(DemoContext&)> run;
};

/// record, label, validate, score, contact_sheet (in that order).
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
