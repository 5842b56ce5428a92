// What relabel prints: the plan (per session: stages, frames, why stale), progress of cluster jobs, and
// the report (stages run or skipped and why, seconds, failed tasks with their logs, verdict changes).
#include <cstdio>

#include "cli/relabel_work.h"
#include "pipeline/yaml_write.h"

namespace mocap::cli {
namespace {

using nlohmann::json;

std::string Join(const std::vector<std::string>& parts, const char* sep) {
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : sep) + p;
  return out;
}

void PrintStage(const char* name, const pipeline::StagePlan& stage) {
  if (stage.run) {
    std::printf("    %s: %zu of %zu shards to run; %s\n", name, stage.todo.size(), stage.shards.size(), Join(stage.why, "; ").c_str());
  } else if (!stage.why.empty()) {
    std::printf("    %s: skipped: %s\n", name, Join(stage.why, "; ").c_str());
  } else {
    std::printf("    %s: up to date\n", name);
  }
}

std::string Transitions(const json& t) {
  std::vector<std::string> parts;
  for (const auto& [what, n] : t.items()) parts.push_back(what + " " + std::to_string(n.get<int64_t>()));
  return Join(parts, ", ");
}

}  // namespace

void PrintPlan(const pipeline::RelabelPlan& plan) {
  int stale = 0;
  for (const pipeline::SessionPlan& s : plan.sessions) stale += (s.label.run || s.validate.run) ? 1 : 0;
  std::printf("relabel plan: %zu sessions, %d with work (%lld label frames, %lld validate frames); planned in %.3f s "
              "(%lld files checked, %lld hashed)\n",
              plan.sessions.size(), stale, static_cast<long long>(plan.FramesToRun(false)),
              static_cast<long long>(plan.FramesToRun(true)), plan.seconds, static_cast<long long>(plan.files_checked),
              static_cast<long long>(plan.files_hashed));
  for (const pipeline::SessionPlan& s : plan.sessions) {
    std::printf("  %s (%lld frames)\n", s.session_dir.string().c_str(), static_cast<long long>(s.frames));
    PrintStage("label", s.label);
    PrintStage("validate", s.validate);
  }
}

json RelabelReport(const RelabelWork& work, const RelabelOutcome& outcome) {
  json sessions = json::array();
  for (const pipeline::SessionPlan& s : work.plan.sessions) {
    json j = {{"session", s.session_dir.string()}, {"frames", s.frames},
              {"label", {{"run", s.label.run}, {"why", s.label.why}, {"shards", s.label.todo.size()}}},
              {"validate", {{"run", s.validate.run}, {"why", s.validate.why}, {"shards", s.validate.todo.size()}}}};
    if (outcome.verdict_changes.contains(s.session_dir.string())) j["verdict_changes"] = outcome.verdict_changes[s.session_dir.string()];
    sessions.push_back(j);
  }
  return {{"ok", outcome.execution.ok()}, {"work", work.dir.string()}, {"planning_seconds", work.plan.seconds},
          {"sessions", sessions}, {"execution", outcome.execution.ToJson()}, {"export", outcome.export_result}};
}

void WriteReport(const RelabelWork& work, const json& report) {
  pipeline::WriteTextAtomically(work.dir / "report.json", report.dump(1) + "\n");
}

void PrintProgress(const pipeline::ExecutionResult& execution) {
  for (const pipeline::StepResult& s : execution.steps)
    std::printf("  %-15s job %-8s %d of %d tasks done\n", s.name.c_str(), s.job_id.c_str(), s.succeeded, s.tasks);
  std::printf(execution.finished ? "all jobs have ended\n"
                                 : "jobs still pending or running: `mocaplabel relabel --status --work DIR` shows them\n");
}

void PrintReport(const RelabelWork& work, const RelabelOutcome& outcome) {
  const pipeline::ExecutionResult& e = outcome.execution;
  if (e.steps.empty()) std::printf("relabel: nothing to label or validate: every run is up to date\n");
  for (const pipeline::StepResult& s : e.steps)
    std::printf("  ran %-15s %d of %d tasks in %.1f s%s\n", s.name.c_str(), s.succeeded, s.tasks, s.seconds,
                s.job_id.empty() ? "" : (" (Slurm job " + s.job_id + ")").c_str());
  for (const pipeline::FailedTask& f : e.failed) {
    std::printf("FAILED %s%s: %s%s\n", f.step.c_str(), f.task < 0 ? "" : (" task " + std::to_string(f.task)).c_str(),
                f.state.c_str(), f.log.empty() ? "" : ("; log " + f.log.string()).c_str());
    if (!f.log_tail.empty()) std::printf("%s", f.log_tail.c_str());
  }
  for (const auto& [session, changes] : outcome.verdict_changes.items()) {
    if (changes["changed"].get<int64_t>() == 0) {
      std::printf("verdicts of %s: none changed (%lld records)\n", session.c_str(), static_cast<long long>(changes["unchanged"].get<int64_t>()));
      continue;
    }
    std::printf("verdicts of %s: %lld changed: %s\n", session.c_str(), static_cast<long long>(changes["changed"].get<int64_t>()),
                Transitions(changes["transitions"]).c_str());
    for (const auto& [object, t] : changes["objects"].items()) std::printf("    %s: %s\n", object.c_str(), Transitions(t).c_str());
  }
  if (!outcome.export_result.is_null()) {
    const bool up_to_date = outcome.export_result.value("up_to_date", false);
    std::printf("export %s: %s\n", work.export_out.string().c_str(), up_to_date ? "up to date, nothing written" : "written");
  }
  if (!e.failed.empty()) std::printf("a rerun of the same relabel redoes only the shards that did not finish\n");
}

}  // namespace mocap::cli
