#pragma once
// The work of a relabel plan as tasks an executor runs (docs/relabel.md): one task per shard to run of
// the label stage, one merge of the sessions labelled in several shards, the same for the validate stage.
// Every task reads the plan file, so a task runs the same on this machine and on a cluster node; each
// shard's run is published whole (publish.h), so a killed task leaves nothing that looks finished.
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/relabel_plan.h"

namespace mocap::pipeline {

enum class RelabelStage { kLabel, kValidate };
std::string_view ToString(RelabelStage stage);  ///< "label", "validate"

/// One shard to run: plan.sessions[session], shard index into that stage's shards.
struct RelabelTask {
  int session = 0, shard = 0;
  int64_t frames = 0;
};

/// The tasks of `stage`, in session then shard order (the array index of a cluster job).
std::vector<RelabelTask> StageTasks(const RelabelPlan& plan, RelabelStage stage);
/// Whether some session runs `stage` in several shards that must then be merged.
bool StageNeedsMerge(const RelabelPlan& plan, RelabelStage stage);

/// Runs `task` of `stage` with `threads` workers (0: one per core). Throws InputError on bad input.
void RunRelabelTask(const RelabelPlan& plan, RelabelStage stage, const RelabelTask& task, int threads,
                    const std::vector<std::string>& command);
/// Merges the shards of every session that ran `stage` in several shards into its run.
void MergeRelabelStage(const RelabelPlan& plan, RelabelStage stage);

/// Verdicts of a finished validation run, "camera/index/object/instance" -> verdict; empty when there is
/// none.
std::map<std::string, std::string> RunVerdicts(const std::filesystem::path& validation_dir);

/// What re-labelling did to the verdicts of one session: {"changed": n, "unchanged": n, "transitions":
/// {"reject->accept": n, ...}, "objects": {name: {transitions}}}; a record new or gone counts as from or
/// to "none".
nlohmann::json VerdictChanges(const std::map<std::string, std::string>& before,
                              const std::map<std::string, std::string>& after);

}  // namespace mocap::pipeline
