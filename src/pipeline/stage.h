#pragma once
// The stage runner (DESIGN.md "Data flow"): a stage declares the files it reads and the folders it
// writes, and runs over a shard (a frame range of a session). Each arrow of the data flow is a file
// format, so a stage can be run alone, skipped when its outputs are up to date (provenance.h), or split
// into shards whose outputs merge into the run one pass writes (shards.h). The stage lists of `demo`,
// `export` and `relabel` are assembled above this module (src/cli), never in src/sim.
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "render/render_context.h"

namespace mocap {
class ProgressSink;
}

namespace mocap::pipeline {

/// A frame range of every camera of a session: [begin, end), end -1 = to the end; `index` of `count`.
struct Shard {
  int index = 0, count = 1;
  int64_t begin = 0, end = -1;
  bool whole() const { return count == 1 && begin == 0 && end < 0; }
  nlohmann::json ToJson() const;  ///< null for the whole session
};

/// What the stages of one run share: where each file is, the options every stage uses, and what each
/// stage reported. A stage reads the paths earlier stages (or the caller) set and sets its own.
struct PipelineContext {
  std::filesystem::path out_dir;   ///< the run's root folder (stages write below it)
  int threads = 0;                 ///< 0: one per core
  RenderContextOptions render_context;
  ProgressSink* progress = nullptr;  ///< not owned; may be null
  std::vector<std::string> command;  ///< argv, recorded in each run.json
  std::filesystem::path session_dir, rig_file, objects_file, labels_dir, validation_dir, truth_dir;
  std::string camera;                           ///< the camera the demo's score and sheet look at
  std::map<std::string, nlohmann::json> results;  ///< stage name -> its summary
  std::map<std::string, std::string> outputs;     ///< name -> path
  std::vector<std::string> notes;                 ///< one line each, for the summary
};

struct Stage {
  std::string name;
  /// The files and folders it reads and the folders it writes, given the context when it starts.
  std::function<std::vector<std::filesystem::path>(const PipelineContext&)> inputs, outputs;
  std::function<void(PipelineContext&, const Shard&)> run;
};

/// Seconds per stage, in order.
using StageSeconds = std::vector<std::pair<std::string, double>>;

/// Runs `stages` in order over `shard`. Before a stage runs, its declared inputs must exist (an
/// InputError names the stage and the missing file). Throws what a stage throws.
StageSeconds RunStages(const std::vector<Stage>& stages, PipelineContext& context, const Shard& shard = {});

}  // namespace mocap::pipeline
