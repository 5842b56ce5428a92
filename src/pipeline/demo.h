#pragma once
// `mocaplabel demo`: the whole tool on the simulated rig, as a list of pipeline stages over one
// PipelineContext (docs/demo.md). The stages (assembled in src/cli/cmd_demo.cc):
//   record         simulate the scenario, write the session with rig.yaml and objects.yaml (record_stage.h)
//   capture        play it through the capture daemon in real time; later stages read the daemon's session
//   label          the labeller on that session, with the rig.yaml and objects.yaml the record stage wrote
//   validate       the SegICP session check of the labels against the measured depth
//   score          labels against the truth (scoring.h)
//   contact_sheet  a grid of labelled frames
// The demo folder is written as <out>.partial and published whole.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/scoring.h"
#include "pipeline/stage.h"
#include "label/labeller.h"
#include "sim/record/sim_recorder.h"
#include "sim/scenario.h"

namespace mocap::pipeline {

struct DemoOptions {
  std::filesystem::path out_dir;  ///< replaced if it holds an earlier demo (demo.json), else must be empty
  int frames = 0;                 ///< 0: the scenario's frame count; else the first N frames
  int threads = 0;                ///< 0: one per core
  /// The validate stage checks the frames whose index is a multiple of this (1: every frame). The
  /// default keeps the default demo within its time budget on 2 cores (docs/demo.md).
  int validate_frame_stride = 1;
  RenderContextOptions context;
  ProgressSink* progress = nullptr;  ///< each stage's progress; not owned, may be null
  void check() const;  ///< throws InputError
};

/// The demo's own stages besides label, validate, record and capture.
Stage MakeScoreStage();
Stage MakeContactSheetStage();
/// The label stage as the demo runs it: instance images and labels.jsonl only (what scoring and the
/// contact sheet read), amodal boxes of objects leaving the image not scored.
Stage MakeDemoLabelStage();

/// Labels a recording of the built-in objects with `calibration` (true, given or perturbed) the way the
/// demo's label stage does, through `mocaplabel label`'s path: rig.yaml and objects.yaml written into
/// <labels_dir>.inputs/, then RunLabel. For accuracy tests and sweeps.
LabelSummary LabelRecording(const sim::RecordResult& record, const sim::RigCalibration& calibration,
                            const std::filesystem::path& labels_dir, const DemoOptions& options);
/// LabelRecording, then the score stage's scoring against the truth.
LabelScores LabelAndScore(const sim::RecordResult& record, const sim::RigCalibration& calibration,
                          const std::filesystem::path& labels_dir, const DemoOptions& options);

/// `scenario` limited to options.frames.
sim::Scenario DemoScenario(const sim::Scenario& scenario, const DemoOptions& options);

struct DemoResult {
  PipelineContext context;
  StageSeconds seconds_per_stage;
  nlohmann::json summary;  ///< what demo.json holds (docs/demo.md)
};

/// Runs `stages` in <out>.partial, writes demo.json and publishes the folder. `expected_frames`: the
/// frames simulated (for dropped_frames).
DemoResult RunDemo(const DemoOptions& options, const std::vector<Stage>& stages, int expected_frames,
                   const std::string& scenario_name, std::vector<std::string> command = {});

}  // namespace mocap::pipeline
