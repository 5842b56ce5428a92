#include "cli/relabel_work.h"

#include <unistd.h>

#include <climits>
#include <cstdlib>

#include "core/check.h"
#include "exporters/export/export.h"
#include "pipeline/json_read.h"
#include "pipeline/relabel_tasks.h"
#include "pipeline/yaml_write.h"

namespace mocap::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using pipeline::RelabelStage;

constexpr int kWorkFormatVersion = 1;

fs::path PlanFile(const fs::path& dir) { return dir / "plan.json"; }

pipeline::ExecutorStep ArrayStep(const RelabelWork& work, RelabelStage stage) {
  pipeline::ExecutorStep step{std::string(pipeline::ToString(stage)), 0, true, {}};
  for (const pipeline::RelabelTask& t : pipeline::StageTasks(work.plan, stage)) step.frames.push_back(t.frames);
  step.tasks = static_cast<int>(step.frames.size());
  return step;
}

std::vector<exporters::ExportInput> ExportInputs(const RelabelWork& work) {
  std::vector<exporters::ExportInput> inputs;
  for (const pipeline::SessionPlan& s : work.plan.sessions) inputs.push_back({s.session_dir, s.labels_dir, {}, false});
  return inputs;
}

exporters::ExportResult Export(const RelabelWork& work, ProgressSink* progress) {
  exporters::ExportOptions options;
  options.format = exporters::ExportFormatFromName(work.export_format);
  options.threads = work.threads;
  return exporters::RunExport(ExportInputs(work), options, work.export_out, work.command, progress);
}

}  // namespace

void SaveWork(RelabelWork& work) {
  work.verdicts_before.clear();
  json before = json::object();
  for (const pipeline::SessionPlan& s : work.plan.sessions)
    if (s.validate.run) {
      work.verdicts_before[s.session_dir.string()] = pipeline::RunVerdicts(s.validation_dir);
      before[s.session_dir.string()] = work.verdicts_before[s.session_dir.string()];
    }
  std::error_code ec;
  fs::remove_all(work.dir / "status", ec);
  fs::create_directories(work.dir);
  const json file = {{"format_version", kWorkFormatVersion}, {"command", work.command},
                     {"plan", pipeline::ToJson(work.plan)}, {"export_out", work.export_out.string()},
                     {"export_format", work.export_format}, {"threads", work.threads}, {"jobs", work.jobs},
                     {"verdicts_before", before}};
  pipeline::WriteTextAtomically(PlanFile(work.dir), file.dump(1) + "\n");
}

RelabelWork ReadWork(const fs::path& dir) {
  const std::string where = PlanFile(dir).string();
  if (!fs::exists(PlanFile(dir))) throw InputError(where, "missing: no relabel was planned in this work folder");
  const json file = pipeline::ReadJsonFile(PlanFile(dir));
  const pipeline::JsonFields f(file, where);
  if (f.Integer("format_version") > kWorkFormatVersion)
    throw InputError(where, "written by a newer mocaplabel (format_version " + std::to_string(f.Integer("format_version")) + ")");
  RelabelWork work;
  work.dir = dir;
  work.command = f.Strings("command");
  work.plan = pipeline::RelabelPlanFromJson(f["plan"], where + " plan");
  work.export_out = f.String("export_out"), work.export_format = f.String("export_format");
  work.threads = static_cast<int>(f.Integer("threads")), work.jobs = static_cast<int>(f.Integer("jobs"));
  for (const auto& [session, verdicts] : f["verdicts_before"].items())
    for (const auto& [key, verdict] : verdicts.items()) work.verdicts_before[session][key] = verdict.get<std::string>();
  return work;
}

std::vector<pipeline::ExecutorStep> WorkSteps(const RelabelWork& work, bool cluster) {
  std::vector<pipeline::ExecutorStep> steps;
  for (RelabelStage stage : {RelabelStage::kLabel, RelabelStage::kValidate}) {
    const pipeline::ExecutorStep step = ArrayStep(work, stage);
    if (step.tasks > 0) steps.push_back(step);
    if (pipeline::StageNeedsMerge(work.plan, stage)) steps.push_back({"merge-" + step.name, 1, false, {}});
  }
  if (cluster && !steps.empty() && !work.export_out.empty()) steps.push_back({"export", 1, false, {}});
  return steps;
}

bool HasExportStep(const std::vector<pipeline::ExecutorStep>& steps) {
  for (const pipeline::ExecutorStep& s : steps)
    if (s.name == "export") return true;
  return false;
}

int RunWorkTask(const fs::path& dir, const std::string& task) {
  const RelabelWork work = ReadWork(dir);
  const size_t colon = task.find(':');
  const std::string step = task.substr(0, colon);
  int index = -1;
  if (colon != std::string::npos) {
    char* end = nullptr;
    index = static_cast<int>(std::strtol(task.c_str() + colon + 1, &end, 10));
    if (*end != '\0' || index < 0) throw InputError("--task", "'" + task + "': expected STEP or STEP:INDEX");
  }
  int threads = work.threads;
  if (const char* slurm_cpus = std::getenv("SLURM_CPUS_PER_TASK"); threads == 0 && slurm_cpus) threads = std::atoi(slurm_cpus);
  // As `label` does: every worker (a thread of this task, or another task beside it) keeps a core busy,
  // and llvmpipe's own rasteriser threads only add hand-over cost (bench/RESULTS.md "Relabel"). Mesa
  // reads the variable at the first EGL display, still to come here.
  if ((threads != 1 || work.jobs > 1) && std::getenv("LP_NUM_THREADS") == nullptr) setenv("LP_NUM_THREADS", "0", 0);
  if (step == "label" || step == "validate") {
    const RelabelStage stage = step == "label" ? RelabelStage::kLabel : RelabelStage::kValidate;
    const std::vector<pipeline::RelabelTask> tasks = pipeline::StageTasks(work.plan, stage);
    if (index < 0 || static_cast<size_t>(index) >= tasks.size())
      throw InputError("--task", "'" + task + "': the plan has " + std::to_string(tasks.size()) + " " + step + " tasks");
    pipeline::RunRelabelTask(work.plan, stage, tasks[static_cast<size_t>(index)], threads, work.command);
  } else if (step == "merge-label" || step == "merge-validate") {
    pipeline::MergeRelabelStage(work.plan, step == "merge-label" ? RelabelStage::kLabel : RelabelStage::kValidate);
  } else if (step == "export" && !work.export_out.empty()) {
    Export(work, nullptr);
  } else {
    throw InputError("--task", "'" + task + "': no such step in the plan");
  }
  pipeline::MarkTaskDone(dir, step, index);
  return 0;
}

void RunWorkExport(const RelabelWork& work, RelabelOutcome& outcome, ProgressSink* progress) {
  outcome.export_result = Export(work, progress).ToJson();
}

void CollectResults(const RelabelWork& work, RelabelOutcome& outcome) {
  if (!outcome.execution.ok()) return;
  for (const pipeline::SessionPlan& s : work.plan.sessions) {
    if (!s.validate.run) continue;
    const auto before = work.verdicts_before.find(s.session_dir.string());
    outcome.verdict_changes[s.session_dir.string()] = pipeline::VerdictChanges(
        before == work.verdicts_before.end() ? std::map<std::string, std::string>{} : before->second,
        pipeline::RunVerdicts(s.validation_dir));
  }
  if (!work.export_out.empty() && fs::exists(work.export_out / "export.json"))
    outcome.export_result = pipeline::ReadJsonFile(work.export_out / "export.json");
}

std::string SelfExecutable() {
  char path[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", path, sizeof(path) - 1);
  if (n <= 0) throw InputError("/proc/self/exe", "cannot find this program's path for the tasks");
  return std::string(path, static_cast<size_t>(n));
}

}  // namespace mocap::cli
