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

/// LD_LIBRARY_PATH + FAKENECT_PATH for a replay of `recording`.
std::map<std::string, std::string> FakenectEnv(const std::filesystem::path& recording);

}  // namespace mocap::testing
