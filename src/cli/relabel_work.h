#pragma once
// The work folder of `mocaplabel relabel` (docs/relabel.md): the plan file every task reads
// (WORK/plan.json, with the verdicts before), the steps an executor runs, the task a worker process runs,
// and the report (WORK/report.json). Above the exporters: the export step is assembled here.
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/executor.h"
#include "pipeline/relabel_plan.h"

namespace mocap {
class ProgressSink;
}

namespace mocap::cli {

struct RelabelWork {
  std::filesystem::path dir;
  std::vector<std::string> command;
  pipeline::RelabelPlan plan;
  std::filesystem::path export_out;  ///< empty: no export stage
  std::string export_format = "bop";
  int threads = 0, jobs = 1;         ///< per task; tasks at a time (local)
  /// Session folder -> its verdicts before (pipeline::RunVerdicts), for the sessions validated again.
  std::map<std::string, std::map<std::string, std::string>> verdicts_before;
};

struct RelabelOutcome {
  pipeline::RelabelPlan plan;
  pipeline::ExecutionResult execution;
  nlohmann::json verdict_changes = nlohmann::json::object();  ///< session -> pipeline::VerdictChanges
  nlohmann::json export_result;                              ///< null: no export
};

/// Writes WORK/plan.json (taking the verdicts before) and clears the task markers of an earlier plan.
void SaveWork(RelabelWork& work);
/// Reads WORK/plan.json; InputError naming it when it is missing or malformed.
RelabelWork ReadWork(const std::filesystem::path& dir);
/// label, merge-label, validate, merge-validate (those with work), and export as a cluster job when
/// `cluster` and there is other work (else the caller exports in process: RunWorkExport).
std::vector<pipeline::ExecutorStep> WorkSteps(const RelabelWork& work, bool cluster);
bool HasExportStep(const std::vector<pipeline::ExecutorStep>& steps);
/// A worker: runs `task` ("label:3", "merge-label", "export", ...) of the plan in `dir`, then marks it done.
int RunWorkTask(const std::filesystem::path& dir, const std::string& task);
/// The export stage in this process; its summary into outcome.export_result.
void RunWorkExport(const RelabelWork& work, RelabelOutcome& outcome, ProgressSink* progress);
/// After the steps: verdict changes of the sessions validated again, the export's summary.
void CollectResults(const RelabelWork& work, RelabelOutcome& outcome);

nlohmann::json RelabelReport(const RelabelWork& work, const RelabelOutcome& outcome);
void WriteReport(const RelabelWork& work, const nlohmann::json& report);  ///< WORK/report.json
void PrintPlan(const pipeline::RelabelPlan& plan);
void PrintReport(const RelabelWork& work, const RelabelOutcome& outcome);
void PrintProgress(const pipeline::ExecutionResult& execution);

/// This binary's path (/proc/self/exe), for the tasks the executors start.
std::string SelfExecutable();

}  // namespace mocap::cli
