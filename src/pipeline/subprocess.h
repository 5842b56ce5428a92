#pragma once
// Child processes for the executors: a task started with its output into a log file, and a command
// (sbatch, squeue, scontrol) run to completion with its output captured.
#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace mocap::pipeline {

struct CommandOutput {
  int exit_code = 0;  ///< 128 + signal when killed by one
  std::string out, err;
};

/// Runs `argv` (argv[0] searched on PATH) to completion. InputError naming argv[0] when it cannot be
/// started (not installed, not executable).
CommandOutput RunCommand(const std::vector<std::string>& argv);

/// Starts `argv` with stdin from /dev/null and stdout and stderr into `log` (truncated); returns its pid.
pid_t StartProcess(const std::vector<std::string>& argv, const std::filesystem::path& log);

/// Waits for any started child; its pid and exit code (128 + signal when killed by one).
std::pair<pid_t, int> WaitAnyChild();

/// The shell-quoted form of `arg` ('...' with ' escaped).
std::string ShellQuote(const std::string& arg);

}  // namespace mocap::pipeline
