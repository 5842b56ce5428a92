// The executors' shared files (logs, markers) and the local executor: tasks as child processes of this
// machine, `jobs` at a time.
#include <chrono>
#include <deque>
#include <fstream>
#include <map>
#include <numeric>
#include <thread>

#include "core/check.h"
#include "core/progress.h"
#include "pipeline/executor.h"
#include "pipeline/subprocess.h"
#include "pipeline/yaml_write.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;

std::string TaskName(const std::string& step, int task) { return task < 0 ? step : step + "-" + std::to_string(task); }

double Since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

fs::path TaskLog(const fs::path& work, const std::string& step, int task) {
  return work / "logs" / (TaskName(step, task) + ".log");
}

fs::path TaskOkMarker(const fs::path& work, const std::string& step, int task) {
  return work / "status" / (TaskName(step, task) + ".ok");
}

void MarkTaskDone(const fs::path& work, const std::string& step, int task) {
  fs::create_directories(work / "status");
  WriteTextAtomically(TaskOkMarker(work, step, task), "ok\n");
}

std::string LogTail(const fs::path& log, int lines) {
  std::ifstream in(log);
  std::deque<std::string> tail;
  for (std::string line; std::getline(in, line);) {
    tail.push_back(line);
    if (static_cast<int>(tail.size()) > lines) tail.pop_front();
  }
  std::string out;
  for (const std::string& line : tail) out += line + "\n";
  return out;
}

nlohmann::json ExecutionResult::ToJson() const {
  nlohmann::json steps_json = nlohmann::json::array(), failed_json = nlohmann::json::array();
  for (const StepResult& s : steps)
    steps_json.push_back({{"step", s.name}, {"tasks", s.tasks}, {"succeeded", s.succeeded}, {"seconds", s.seconds},
                          {"job_id", s.job_id}});
  for (const FailedTask& f : failed)
    failed_json.push_back({{"step", f.step}, {"task", f.task}, {"state", f.state}, {"log", f.log.string()},
                           {"log_tail", f.log_tail}});
  return {{"steps", steps_json}, {"failed", failed_json}, {"finished", finished}, {"ok", ok()}, {"seconds", seconds}};
}

void LocalExecutorOptions::check() const {
  if (jobs < 0) throw InputError("relabel", "--jobs must be >= 0");
}

ExecutionResult RunLocal(const std::vector<ExecutorStep>& steps, const std::vector<std::string>& base,
                         const fs::path& work, const LocalExecutorOptions& options, ProgressSink* progress) {
  options.check();
  const int jobs = options.jobs > 0 ? options.jobs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const auto start = std::chrono::steady_clock::now();
  ExecutionResult result;
  for (const ExecutorStep& step : steps) {
    StepResult sr{step.name, step.tasks, 0, 0, ""};
    if (!result.failed.empty()) {  // an earlier step failed: this one depends on it
      result.failed.push_back({step.name, -1, "not run: an earlier step failed", {}, ""});
      result.steps.push_back(sr);
      continue;
    }
    const auto step_start = std::chrono::steady_clock::now();
    const bool by_frames = step.frames.size() == static_cast<size_t>(step.tasks);
    const int64_t total = by_frames ? std::accumulate(step.frames.begin(), step.frames.end(), int64_t{0}) : step.tasks;
    const std::string what = step.array ? Str(step.name, ", ", step.tasks, step.tasks == 1 ? " shard" : " shards") : step.name;
    Progress counter(progress, what, total, by_frames ? "frames" : "tasks");
    std::map<pid_t, int> running;
    int next = 0;
    while (next < step.tasks || !running.empty()) {
      while (next < step.tasks && static_cast<int>(running.size()) < jobs) {
        const int task = step.array ? next : -1;
        std::vector<std::string> argv = base;
        argv.insert(argv.end(), {"--task", step.array ? step.name + ":" + std::to_string(task) : step.name});
        std::error_code ec;
        fs::remove(TaskOkMarker(work, step.name, task), ec);
        running[StartProcess(argv, TaskLog(work, step.name, task))] = task;
        ++next;
      }
      const auto [pid, code] = WaitAnyChild();
      const auto it = running.find(pid);
      if (it == running.end()) continue;
      const int task = it->second;
      running.erase(it);
      if (code == 0 && fs::exists(TaskOkMarker(work, step.name, task))) {
        ++sr.succeeded;
        counter.Advance(by_frames ? step.frames[static_cast<size_t>(std::max(task, 0))] : 1);
      } else {
        const fs::path log = TaskLog(work, step.name, task);
        result.failed.push_back({step.name, task, "exit status " + std::to_string(code), log, LogTail(log)});
      }
    }
    counter.Finish();
    sr.seconds = Since(step_start);
    result.steps.push_back(sr);
  }
  result.seconds = Since(start);
  return result;
}

}  // namespace mocap::pipeline
