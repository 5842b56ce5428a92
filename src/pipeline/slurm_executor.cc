// The Slurm executor (executor.h): sbatch per step with afterok dependencies, followed with squeue and
// scontrol. Slurm's own state is used only to say why a task failed; what is done is what the task
// markers say, so a job Slurm has forgotten (MinJobAge) is still judged right.
#include <chrono>
#include <ctime>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "core/check.h"
#include "core/progress.h"
#include "pipeline/executor.h"
#include "pipeline/json_read.h"
#include "pipeline/subprocess.h"
#include "pipeline/yaml_write.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path JobsFile(const fs::path& work) { return work / "slurm" / "jobs.json"; }

std::string FirstLine(const std::string& text) {
  const std::string line = text.substr(0, text.find('\n'));
  return line.empty() ? "(no message)" : line;
}

/// The job script of a step: runs the task of the array index (or the single job).
fs::path WriteJobScript(const ExecutorStep& step, const std::vector<std::string>& base, const fs::path& work) {
  std::string command;
  for (const std::string& arg : base) command += ShellQuote(arg) + " ";
  command += "--task " + (step.array ? ShellQuote(step.name + ":") + "\"$SLURM_ARRAY_TASK_ID\"" : ShellQuote(step.name));
  const fs::path script = work / "slurm" / (step.name + ".sh");
  WriteTextAtomically(script, "#!/bin/sh\n# mocaplabel relabel, step " + step.name +
                                  " (written by relabel; one task per array index)\nexec " + command + "\n");
  fs::permissions(script, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec, fs::perm_options::add);
  return script;
}

std::vector<std::string> SbatchArgv(const ExecutorStep& step, const fs::path& work, const SlurmOptions& o,
                                    const std::string& after) {
  std::vector<std::string> argv = {"sbatch", "--parsable", "--job-name=mocaplabel-" + step.name};
  argv.push_back("--output=" + (work / "logs" / (step.array ? step.name + "-%a.log" : step.name + ".log")).string());
  if (step.array)
    argv.push_back("--array=0-" + std::to_string(step.tasks - 1) + (o.max_running > 0 ? "%" + std::to_string(o.max_running) : ""));
  if (!after.empty()) argv.push_back("--dependency=afterok:" + after);
  if (!o.partition.empty()) argv.push_back("--partition=" + o.partition);
  if (!o.time_limit.empty()) argv.push_back("--time=" + o.time_limit);
  if (!o.memory.empty()) argv.push_back("--mem=" + o.memory);
  if (o.cpus_per_task > 0) argv.push_back("--cpus-per-task=" + std::to_string(o.cpus_per_task));
  argv.insert(argv.end(), o.sbatch_args.begin(), o.sbatch_args.end());
  argv.push_back((work / "slurm" / (step.name + ".sh")).string());
  return argv;
}

void CancelJobs(const std::vector<StepResult>& submitted) {
  for (const StepResult& s : submitted) {
    try {
      RunCommand({"scancel", s.job_id});
    } catch (const InputError&) {  // best effort: the submission error is what the user needs to see
    }
  }
}

struct JobState {
  std::string state;  ///< JobState, e.g. COMPLETED, CANCELLED, FAILED
  std::string reason;
  std::string start, end;  ///< StartTime, EndTime (ISO 8601 without zone; "Unknown" when not run)
};

/// Seconds from the earliest start to the latest end of a job's tasks (0 when unknown).
double JobSeconds(const std::map<int, JobState>& states) {
  auto parse = [](const std::string& t) -> int64_t {
    std::tm tm{};
    if (t.size() < 19 || !strptime(t.c_str(), "%Y-%m-%dT%H:%M:%S", &tm)) return -1;
    return static_cast<int64_t>(timegm(&tm));
  };
  int64_t first = -1, last = -1;
  for (const auto& [task, s] : states) {
    const int64_t a = parse(s.start), b = parse(s.end);
    if (a >= 0 && (first < 0 || a < first)) first = a;
    if (b >= 0 && b > last) last = b;
  }
  return first >= 0 && last >= first ? static_cast<double>(last - first) : 0.0;
}

/// scontrol's view of a job's tasks: array task id (-1 for a single job) -> state. Empty when Slurm no
/// longer knows the job.
std::map<int, JobState> ScontrolStates(const std::string& job_id) {
  std::map<int, JobState> states;
  const CommandOutput r = RunCommand({"scontrol", "show", "job", "-o", job_id});
  if (r.exit_code != 0) return states;
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    int task = -1;
    JobState s;
    for (std::string word; words >> word;) {
      const size_t eq = word.find('=');
      if (eq == std::string::npos) continue;
      const std::string key = word.substr(0, eq), value = word.substr(eq + 1);
      if (key == "ArrayTaskId") task = std::atoi(value.c_str());
      if (key == "JobState") s.state = value;
      if (key == "Reason") s.reason = value;
      if (key == "StartTime") s.start = value;
      if (key == "EndTime") s.end = value;
    }
    if (!s.state.empty()) states[task] = s;
  }
  return states;
}

/// Job ids (array job ids as submitted) squeue still lists as pending or running.
std::set<std::string> ActiveJobs(const std::vector<std::string>& ids) {
  std::string list;
  for (const std::string& id : ids) list += (list.empty() ? "" : ",") + id;
  const CommandOutput r = RunCommand({"squeue", "-h", "-r", "-o", "%F %T", "-j", list});
  if (r.exit_code != 0) {
    if (r.err.find("Invalid job id") != std::string::npos) return {};  // none known any more
    throw InputError("squeue", FirstLine(r.err) + " (is the Slurm controller reachable?)");
  }
  std::set<std::string> active;
  std::istringstream lines(r.out);
  for (std::string id, state; lines >> id >> state;)
    if (state != "COMPLETED" && state != "CANCELLED" && state != "FAILED" && state != "TIMEOUT") active.insert(id);
  return active;
}

}  // namespace

void SlurmOptions::check() const {
  if (cpus_per_task < 0) throw InputError("relabel", "--cpus-per-task must be >= 0");
  if (max_running < 0) throw InputError("relabel", "--max-running must be >= 0");
  if (!(poll_seconds > 0)) throw InputError("relabel", "the poll interval must be > 0");
}

std::vector<StepResult> SubmitSlurm(const std::vector<ExecutorStep>& steps, const std::vector<std::string>& base,
                                    const fs::path& work, const SlurmOptions& options) {
  options.check();
  fs::create_directories(work / "slurm"), fs::create_directories(work / "logs"), fs::create_directories(work / "status");
  std::vector<StepResult> submitted;
  json jobs = json::array();
  for (const ExecutorStep& step : steps) {
    WriteJobScript(step, base, work);
    for (int k = step.array ? 0 : -1; k < (step.array ? step.tasks : 0); ++k) fs::remove(TaskOkMarker(work, step.name, k));
    const std::vector<std::string> argv = SbatchArgv(step, work, options, submitted.empty() ? "" : submitted.back().job_id);
    CommandOutput r;
    try {
      r = RunCommand(argv);
    } catch (const InputError&) {
      CancelJobs(submitted);
      throw InputError("sbatch", "not found: this machine has no Slurm client (install slurm-client, or use --executor local)");
    }
    const std::string first = FirstLine(r.out), id = first.substr(0, first.find(';'));  // --parsable: "id[;cluster]"
    if (r.exit_code != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
      CancelJobs(submitted);
      throw InputError("sbatch", "refused the " + step.name + " job: " + FirstLine(r.err + r.out));
    }
    submitted.push_back({step.name, step.tasks, 0, 0, id});
    jobs.push_back({{"step", step.name}, {"job_id", id}, {"tasks", step.tasks}, {"array", step.array}, {"frames", step.frames}});
  }
  WriteTextAtomically(JobsFile(work), json{{"jobs", jobs}}.dump(2) + "\n");
  return submitted;
}

bool SlurmJobsActive(const fs::path& work) {
  if (!fs::exists(JobsFile(work))) return false;
  std::vector<std::string> ids;
  for (const json& j : ReadJsonFile(JobsFile(work)).at("jobs")) ids.push_back(j.at("job_id").get<std::string>());
  return !ids.empty() && !ActiveJobs(ids).empty();
}

ExecutionResult FollowSlurm(const fs::path& work, bool wait, double poll_seconds, ProgressSink* progress) {
  const auto start = std::chrono::steady_clock::now();
  if (!fs::exists(JobsFile(work))) throw InputError(JobsFile(work).string(), "missing: no Slurm jobs were submitted from this work folder");
  const json file = ReadJsonFile(JobsFile(work));
  std::vector<ExecutorStep> steps;
  std::vector<std::string> ids;
  for (const json& j : file.at("jobs")) {
    const JsonFields f(j, JobsFile(work).string());
    steps.push_back({f.String("step"), static_cast<int>(f.Integer("tasks")), f.Bool("array"), {}});
    ids.push_back(f.String("job_id"));
  }
  Progress counter(progress, "slurm jobs", static_cast<int64_t>(ids.size()), "jobs");
  std::set<std::string> active = ActiveJobs(ids);
  while (wait && !active.empty()) {
    std::this_thread::sleep_for(std::chrono::duration<double>(poll_seconds));
    active = ActiveJobs(ids);
    counter.Advance(static_cast<int64_t>(ids.size() - active.size()) - counter.done());
  }
  counter.Finish();
  ExecutionResult result;
  result.finished = active.empty();
  for (size_t i = 0; i < steps.size(); ++i) {
    const ExecutorStep& step = steps[i];
    StepResult sr{step.name, step.tasks, 0, 0, ids[i]};
    const std::map<int, JobState> states = result.finished ? ScontrolStates(ids[i]) : std::map<int, JobState>{};
    sr.seconds = JobSeconds(states);
    for (int k = step.array ? 0 : -1; k < (step.array ? step.tasks : 0); ++k) {
      if (fs::exists(TaskOkMarker(work, step.name, k))) {
        ++sr.succeeded;
        continue;
      }
      if (!result.finished) continue;
      const auto it = states.count(k) ? states.find(k) : states.find(-1);  // a pending array shows as one line
      std::string state = it == states.end() ? "no success marker (Slurm no longer knows the job)"
                                             : it->second.state + (it->second.reason.empty() || it->second.reason == "None"
                                                                       ? "" : " (" + it->second.reason + ")");
      const fs::path log = TaskLog(work, step.name, k);
      result.failed.push_back({step.name, k, state, fs::exists(log) ? log : fs::path(), LogTail(log)});
    }
    result.steps.push_back(sr);
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace mocap::pipeline
