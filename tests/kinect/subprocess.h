#pragma once
// Runs a program with extra environment variables (the fakenect library path and recording), waiting
// for it to finish. Test support only.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace mocap::testing {

struct ProcessResult {
  int exit_code = -1;  ///< -1 when it did not exit normally
  std::string output;  ///< stdout and stderr together
};

ProcessResult RunProcess(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env,
                         const std::filesystem::path& log_file);

/// The argument and environment arrays of posix_spawn: `argv` as given, and this process's environment
/// with `env` added (an entry of `env` replaces a variable of the same name). The pointers point into
/// the struct's strings, so it must outlive the spawn call.
struct SpawnArgs {
  SpawnArgs(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env);
  SpawnArgs(const SpawnArgs&) = delete;
  SpawnArgs& operator=(const SpawnArgs&) = delete;
  std::vector<std::string> arg_strings, env_strings;
  std::vector<char*> args, envp;  ///< null-terminated
};

/// LD_LIBRARY_PATH + FAKENECT_PATH for a replay of `recording`.
std::map<std::string, std::string> FakenectEnv(const std::filesystem::path& recording);

}  // namespace mocap::testing
