#pragma once
// A child process for the daemon's end-to-end tests: started with extra environment variables, its
// stdout read line by line (the daemon and the emulator print where they listen), stderr to a log
// file, killed or waited for. Test support only.
#include <sys/types.h>

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace mocap::testing {

class ChildProcess {
 public:
  ChildProcess(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env,
               const std::filesystem::path& log_file);
  ~ChildProcess();  ///< SIGKILLs it if it still runs
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// The next stdout line (without '\n'), or nullopt after `timeout_ms` or at end of output.
  std::optional<std::string> ReadLine(int timeout_ms);
  void Signal(int signal);
  /// Waits up to timeout_ms; the exit status, 128 + signal when killed, nullopt when still running.
  std::optional<int> Wait(int timeout_ms);
  pid_t pid() const { return pid_; }
  std::string Log() const;

 private:
  pid_t pid_ = -1;
  int stdout_fd_ = -1;
  std::string buffer_;
  std::filesystem::path log_file_;
  std::optional<int> status_;
};

}  // namespace mocap::testing
