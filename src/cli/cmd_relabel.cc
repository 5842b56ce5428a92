// mocaplabel relabel S... : label, validate and export again what is stale against the current rig,
// object library and meshes (src/pipeline/relabel_plan.h), on all cores or on a Slurm cluster
// (src/pipeline/executor.h). docs/relabel.md.
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <thread>

#include "cli/commands.h"
#include "cli/parse_args.h"
#include "cli/progress_flag.h"
#include "cli/relabel_work.h"
#include "core/check.h"
#include "pipeline/hash_cache.h"

namespace mocap::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Flags {
  std::vector<std::string> sessions, stages = {"label", "validate"}, sbatch_args;
  std::string rig, objects, executor = "local", work = "relabel-work", task, export_format = "bop", export_out;
  int64_t shard_frames = 0;
  int jobs = 0, threads = -1;
  bool dry_run = false, json = false, no_wait = false, status = false, relabel_moved = false;
  pipeline::SlurmOptions slurm;
};

void AddFlags(CLI::App& app, Flags& f) {
  app.add_option("sessions", f.sessions, "session folders");
  app.add_option("--rig", f.rig, "rig calibration YAML (default: the one each label run recorded)");
  app.add_option("--objects", f.objects, "object library YAML (default: the one each run recorded, else SESSION/objects.yaml)");
  app.add_option("--stages", f.stages, "stages to redo when stale: label, validate, export (export needs --export-out)")
      ->delimiter(',')->check(CLI::IsMember({"label", "validate", "export"}))->capture_default_str();
  app.add_option("--export-format", f.export_format, "dataset format: bop, coco, segpairs or tum")->capture_default_str();
  app.add_option("--export-out", f.export_out, "dataset folder; adds the export stage");
  app.add_option("--executor", f.executor, "local (this machine's cores) or slurm (sbatch)")
      ->check(CLI::IsMember({"local", "slurm"}))->capture_default_str();
  app.add_option("--shard-frames", f.shard_frames, "frames per shard (0: one shard per session)")->check(CLI::Range(int64_t{0}, int64_t{1} << 40));
  app.add_option("--jobs", f.jobs, "local: tasks at a time (0: one per core)")->check(CLI::Range(0, 4096));
  app.add_option("--threads", f.threads, "worker threads per task (default: cores / jobs; Slurm: --cpus-per-task)")->check(CLI::Range(0, 256));
  app.add_option("--work", f.work, "folder for the plan, task logs and job scripts (on a shared file system for Slurm)")->capture_default_str();
  app.add_option("--partition", f.slurm.partition, "Slurm: partition");
  app.add_option("--time", f.slurm.time_limit, "Slurm: time limit per task (sbatch --time)");
  app.add_option("--mem", f.slurm.memory, "Slurm: memory per task (sbatch --mem)");
  app.add_option("--cpus-per-task", f.slurm.cpus_per_task, "Slurm: CPUs per task")->check(CLI::Range(0, 4096));
  app.add_option("--max-running", f.slurm.max_running, "Slurm: array tasks running at once (--array=0-N%K; 0: no limit)")->check(CLI::Range(0, 1 << 20));
  app.add_option("--sbatch-arg", f.sbatch_args, "Slurm: one more sbatch argument (repeatable), e.g. --sbatch-arg=--account=lab")
      ->allow_extra_args(false);
  app.add_option("--poll-seconds", f.slurm.poll_seconds, "Slurm: squeue interval while waiting")->check(CLI::Range(0.05, 600.0));
  app.add_flag("--no-wait", f.no_wait, "Slurm: submit and exit; a later relabel or relabel --status picks the jobs up");
  app.add_flag("--status", f.status, "Slurm: the state of the jobs submitted from --work, and the report once they are done");
  app.add_flag("--dry-run", f.dry_run, "print the plan (per session: stages, frames, why stale) and exit");
  app.add_flag("--relabel-moved", f.relabel_moved, "relabel a session whose runs name another folder (it was moved)");
  app.add_flag("--json", f.json, "print the plan or the report as one JSON object");
  app.add_option("--task", f.task, "run one task of the plan in --work (what the executors start)")->group("");
}

pipeline::RelabelPlanOptions PlanOptions(const Flags& f) {
  pipeline::RelabelPlanOptions o;
  o.rig_file = f.rig, o.objects_file = f.objects;
  o.label = std::find(f.stages.begin(), f.stages.end(), "label") != f.stages.end();
  o.validate = std::find(f.stages.begin(), f.stages.end(), "validate") != f.stages.end();
  o.shard_frames = f.shard_frames;
  o.relabel_moved = f.relabel_moved;
  return o;
}

int CoresOf() { return static_cast<int>(std::max(1u, std::thread::hardware_concurrency())); }

RelabelWork NewWork(const Flags& f, int argc, char** argv) {
  RelabelWork w;
  w.dir = fs::absolute(f.work).lexically_normal();
  w.command = CommandLine(argc, argv);
  const bool exporting = !f.export_out.empty() || std::find(f.stages.begin(), f.stages.end(), "export") != f.stages.end();
  if (exporting && f.export_out.empty()) throw InputError("relabel", "the export stage needs --export-out DIR");
  if (exporting) w.export_out = fs::absolute(f.export_out).lexically_normal(), w.export_format = f.export_format;
  const int jobs = f.jobs > 0 ? f.jobs : CoresOf();
  if (f.threads >= 0) w.threads = f.threads;
  else w.threads = f.executor == "slurm" ? f.slurm.cpus_per_task : std::max(1, CoresOf() / jobs);
  w.jobs = jobs;
  return w;
}

int Finish(const RelabelWork& work, const RelabelOutcome& outcome, bool json_out) {
  const json report = RelabelReport(work, outcome);
  WriteReport(work, report);
  if (json_out) std::printf("%s\n", report.dump().c_str());
  else PrintReport(work, outcome);
  return outcome.execution.ok() ? 0 : 1;
}

/// Jobs an earlier relabel submitted from this work folder have ended: say how, before planning again.
void NoteEndedJobs(const fs::path& work) {
  if (!fs::exists(work / "slurm" / "jobs.json")) return;
  const pipeline::ExecutionResult earlier = pipeline::FollowSlurm(work, false);
  if (earlier.failed.empty()) return;
  std::fprintf(stderr, "relabel: the jobs submitted earlier from %s ended with %zu failed tasks; planning again redoes them:\n",
               work.string().c_str(), earlier.failed.size());
  for (const pipeline::FailedTask& t : earlier.failed)
    std::fprintf(stderr, "  %s%s: %s%s\n", t.step.c_str(), t.task < 0 ? "" : (" task " + std::to_string(t.task)).c_str(),
                 t.state.c_str(), t.log.empty() ? "" : ("; log " + t.log.string()).c_str());
}

int Status(const Flags& f) {
  RelabelWork work = ReadWork(fs::absolute(f.work));
  RelabelOutcome outcome{work.plan, pipeline::FollowSlurm(work.dir, false), json::object(), nullptr};
  if (!outcome.execution.finished) {
    if (f.json) std::printf("%s\n", json{{"finished", false}, {"execution", outcome.execution.ToJson()}}.dump().c_str());
    else PrintProgress(outcome.execution);
    return 0;
  }
  CollectResults(work, outcome);
  return Finish(work, outcome, f.json);
}

}  // namespace

int RunRelabel(int argc, char** argv) {
  CLI::App app{"Label, validate and export again what is stale, on all cores or on a Slurm cluster", "mocaplabel relabel"};
  Flags f;
  AddFlags(app, f);
  ProgressFlags progress_flags;
  AddProgressFlags(app, progress_flags);
  MOCAP_PARSE(app, argc, argv);
  const std::unique_ptr<ProgressSink> progress = ApplyProgressFlags(progress_flags);
  f.slurm.sbatch_args = f.sbatch_args;
  if (!f.task.empty()) return RunWorkTask(fs::absolute(f.work), f.task);
  if (f.status) return Status(f);
  if (f.sessions.empty()) throw InputError("relabel", "no session given");

  RelabelWork work = NewWork(f, argc, argv);
  if (f.executor == "slurm" && !f.dry_run && pipeline::SlurmJobsActive(work.dir)) {
    std::fprintf(stderr, "relabel: jobs submitted from %s are still running: following them\n", work.dir.string().c_str());
    work = ReadWork(work.dir);
    RelabelOutcome outcome{work.plan, pipeline::FollowSlurm(work.dir, !f.no_wait, f.slurm.poll_seconds, progress.get()),
                           json::object(), nullptr};
    if (!outcome.execution.finished) return (PrintProgress(outcome.execution), 0);
    CollectResults(work, outcome);
    return Finish(work, outcome, f.json);
  }
  if (f.executor == "slurm" && !f.dry_run) NoteEndedJobs(work.dir);
  pipeline::HashCache cache;
  std::vector<fs::path> sessions(f.sessions.begin(), f.sessions.end());
  work.plan = pipeline::PlanRelabel(sessions, PlanOptions(f), cache);
  cache.Save();
  if (f.dry_run) {
    if (f.json) std::printf("%s\n", json{{"plan", ToJson(work.plan)}}.dump().c_str());
    else PrintPlan(work.plan);
    return 0;
  }
  if (!f.json) PrintPlan(work.plan);
  SaveWork(work);  // the plan file every task reads, and the verdicts before
  RelabelOutcome outcome{work.plan, {}, json::object(), nullptr};
  const std::vector<pipeline::ExecutorStep> steps = WorkSteps(work, f.executor == "slurm");
  const std::vector<std::string> base = {SelfExecutable(), "relabel", "--work", work.dir.string()};
  if (f.executor == "slurm" && !steps.empty()) {
    const auto submitted = pipeline::SubmitSlurm(steps, base, work.dir, f.slurm);
    for (const auto& s : submitted) std::fprintf(stderr, "relabel: submitted %s as Slurm job %s (%d tasks)\n", s.name.c_str(), s.job_id.c_str(), s.tasks);
    outcome.execution = pipeline::FollowSlurm(work.dir, !f.no_wait, f.slurm.poll_seconds, progress.get());
    if (!outcome.execution.finished) return (PrintProgress(outcome.execution), 0);
  } else {
    outcome.execution = pipeline::RunLocal(steps, base, work.dir, {f.jobs}, progress.get());
  }
  CollectResults(work, outcome);
  if (outcome.execution.ok() && !work.export_out.empty() && !HasExportStep(steps)) RunWorkExport(work, outcome, progress.get());
  return Finish(work, outcome, f.json);
}

}  // namespace mocap::cli
