#pragma once
// Executors (docs/relabel.md "Executors"): run a list of steps, each one job or an array of tasks, every
// step after the previous one succeeded. A task is the mocaplabel binary itself, `BASE --task
// <step>[:<index>]`, so a task runs the same on this machine and on a cluster node (a shared file
// system assumed). A task that succeeds writes its marker (TaskOkMarker): what counts as done is what
// the files say, whatever the executor or the scheduler remembers.
//   local: child processes on this machine, `jobs` at a time, each logged to WORK/logs.
//   Slurm: one `sbatch --array` per step, each --dependency=afterok on the one before; followed with
//          squeue and scontrol (no accounting daemon needed); WORK/slurm/jobs.json lets a later call
//          pick the jobs up.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace mocap {
class ProgressSink;
}

namespace mocap::pipeline {

struct ExecutorStep {
  std::string name;              ///< "label", "merge-label", ...: the --task argument
  int tasks = 1;                 ///< >= 1
  bool array = false;            ///< one task per index (--task name:K), else one job (--task name)
  std::vector<int64_t> frames;   ///< per task, for progress (empty: tasks are counted)
};

struct FailedTask {
  std::string step;
  int task = -1;            ///< -1: a single job
  std::string state;        ///< "exit status 1", "CANCELLED", "not run: an earlier step failed", ...
  std::filesystem::path log;
  std::string log_tail;     ///< its last lines
};

struct StepResult {
  std::string name;
  int tasks = 0, succeeded = 0;
  double seconds = 0;
  std::string job_id;  ///< Slurm only
};

struct ExecutionResult {
  std::vector<StepResult> steps;
  std::vector<FailedTask> failed;
  bool finished = true;  ///< false: jobs still pending or running (Slurm, not waited for)
  double seconds = 0;
  bool ok() const { return finished && failed.empty(); }
  nlohmann::json ToJson() const;
};

/// WORK/logs/<step>-<task>.log (a single job: <step>.log).
std::filesystem::path TaskLog(const std::filesystem::path& work, const std::string& step, int task);
/// WORK/status/<step>-<task>.ok (a single job: <step>.ok), written by a task that succeeded.
std::filesystem::path TaskOkMarker(const std::filesystem::path& work, const std::string& step, int task);
/// Writes the marker (atomically).
void MarkTaskDone(const std::filesystem::path& work, const std::string& step, int task);
/// The last `lines` lines of a log ("" when it is missing).
std::string LogTail(const std::filesystem::path& log, int lines = 5);

struct LocalExecutorOptions {
  int jobs = 0;  ///< tasks at a time; 0: one per core
  void check() const;
};

/// Runs `steps` in order on this machine; a step whose task failed stops the run (later steps are
/// reported not run). Progress in frames (or tasks) per step.
ExecutionResult RunLocal(const std::vector<ExecutorStep>& steps, const std::vector<std::string>& base,
                         const std::filesystem::path& work, const LocalExecutorOptions& options,
                         ProgressSink* progress = nullptr);

struct SlurmOptions {
  std::string partition, time_limit, memory;  ///< sbatch --partition, --time, --mem ("" = cluster default)
  int cpus_per_task = 0;                      ///< --cpus-per-task (0 = cluster default)
  int max_running = 0;                        ///< array throttle (--array=0-N%M); 0 = none
  std::vector<std::string> sbatch_args;       ///< more sbatch arguments, as given
  double poll_seconds = 1.0;                  ///< squeue interval while following
  void check() const;
};

/// Writes a job script per step (WORK/slurm/<step>.sh) and submits them, each afterok the previous;
/// records WORK/slurm/jobs.json. InputError naming sbatch and its message when it is missing, cannot
/// reach the controller or refuses a job; the jobs submitted before are cancelled then.
std::vector<StepResult> SubmitSlurm(const std::vector<ExecutorStep>& steps, const std::vector<std::string>& base,
                                    const std::filesystem::path& work, const SlurmOptions& options);
/// Whether WORK/slurm/jobs.json names jobs Slurm still has pending or running.
bool SlurmJobsActive(const std::filesystem::path& work);
/// Follows the jobs of WORK/slurm/jobs.json: until none is pending or running (`wait`), or once. The
/// result counts what the markers say; failed tasks carry Slurm's state when it still knows the job.
ExecutionResult FollowSlurm(const std::filesystem::path& work, bool wait, double poll_seconds = 1.0,
                            ProgressSink* progress = nullptr);

}  // namespace mocap::pipeline
