#include "pipeline/subprocess.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/check.h"
#include "session/import/text_parse.h"

extern char** environ;

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;

std::vector<char*> Argv(const std::vector<std::string>& argv) {
  std::vector<char*> out;
  for (const std::string& a : argv) out.push_back(const_cast<char*>(a.c_str()));
  out.push_back(nullptr);
  return out;
}

pid_t Spawn(const std::vector<std::string>& argv, const std::string& out_file, const std::string& err_file) {
  MOCAP_CHECK(!argv.empty(), "no program to start");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (err_file == out_file) posix_spawn_file_actions_adddup2(&actions, 1, 2);
  else posix_spawn_file_actions_addopen(&actions, 2, err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  std::vector<char*> args = Argv(argv);
  const int error = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) throw InputError(argv[0], std::string("cannot be started: ") + std::strerror(error));
  return pid;
}

int ExitCode(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

}  // namespace

CommandOutput RunCommand(const std::vector<std::string>& argv) {
  char out_name[] = "/tmp/mocaplabel-cmd-out-XXXXXX", err_name[] = "/tmp/mocaplabel-cmd-err-XXXXXX";
  const int out_fd = mkstemp(out_name), err_fd = mkstemp(err_name);
  if (out_fd < 0 || err_fd < 0) throw InputError("/tmp", std::string("cannot create a temporary file: ") + std::strerror(errno));
  ::close(out_fd), ::close(err_fd);
  CommandOutput result;
  try {
    const pid_t pid = Spawn(argv, out_name, err_name);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    result.exit_code = ExitCode(status);
    // posix_spawnp reports a missing program as exit 127 from the child on some libcs.
    result.out = import::ReadTextFile(out_name), result.err = import::ReadTextFile(err_name);
  } catch (...) {
    ::unlink(out_name), ::unlink(err_name);
    throw;
  }
  ::unlink(out_name), ::unlink(err_name);
  if (result.exit_code == 127 && result.out.empty() && result.err.empty())
    throw InputError(argv[0], "cannot be started: not found on PATH");
  return result;
}

pid_t StartProcess(const std::vector<std::string>& argv, const fs::path& log) {
  fs::create_directories(log.parent_path());
  return Spawn(argv, log.string(), log.string());
}

std::pair<pid_t, int> WaitAnyChild() {
  int status = 0;
  pid_t pid = -1;
  while ((pid = ::waitpid(-1, &status, 0)) < 0 && errno == EINTR) {
  }
  if (pid < 0) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
  return {pid, ExitCode(status)};
}

std::string ShellQuote(const std::string& arg) {
  std::string out = "'";
  for (char c : arg) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace mocap::pipeline
