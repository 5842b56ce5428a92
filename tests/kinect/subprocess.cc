#include "subprocess.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cstring>
#include <fstream>
#include <sstream>

extern char** environ;

namespace mocap::testing {

SpawnArgs::SpawnArgs(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env)
    : arg_strings(argv) {
  for (char** e = environ; *e; ++e) {
    const std::string entry = *e;
    const std::string key = entry.substr(0, entry.find('='));
    if (!env.count(key)) env_strings.push_back(entry);
  }
  for (const auto& [key, value] : env) env_strings.push_back(key + "=" + value);
  for (auto& s : env_strings) envp.push_back(s.data());
  envp.push_back(nullptr);
  for (auto& s : arg_strings) args.push_back(s.data());
  args.push_back(nullptr);
}

ProcessResult RunProcess(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env,
                         const std::filesystem::path& log_file) {
  SpawnArgs spawn(argv, env);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  ProcessResult result;
  const int rc = posix_spawn(&pid, spawn.args[0], &actions, nullptr, spawn.args.data(), spawn.envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    result.output = std::string("posix_spawn failed: ") + std::strerror(rc);
    return result;
  }
  int status = 0;
  waitpid(pid, &status, 0);
  if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  std::ifstream in(log_file);
  std::stringstream text;
  text << in.rdbuf();
  result.output = text.str();
  return result;
}

std::map<std::string, std::string> FakenectEnv(const std::filesystem::path& recording) {
  return {{"LD_LIBRARY_PATH", "/usr/lib/x86_64-linux-gnu/fakenect"}, {"FAKENECT_PATH", recording.string()}};
}

}  // namespace mocap::testing
