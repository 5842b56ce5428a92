#include "full_disk.h"

#include <sched.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace mocap::testing {

std::string RunOnFullDiskInChild(const std::filesystem::path& mount_point, const std::function<void(const SayFn&)>& body) {
  int fds[2];
  if (::pipe(fds) != 0) return "FAIL pipe failed";
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(fds[0]);
    const SayFn say = [&](const std::string& text) {
      (void)!::write(fds[1], text.data(), text.size());
      ::_exit(0);
    };
    const int flags = ::geteuid() == 0 ? CLONE_NEWNS : (CLONE_NEWUSER | CLONE_NEWNS);
    if (::unshare(flags) != 0) say(std::string("SKIP unshare: ") + std::strerror(errno));
    if (::mount("none", "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0 ||
        ::mount("tmpfs", mount_point.c_str(), "tmpfs", 0, "size=1m") != 0)
      say(std::string("SKIP mount tmpfs: ") + std::strerror(errno));
    body(say);
    say("FAIL the test body returned without a result");
  }
  ::close(fds[1]);
  std::string message;
  char buffer[512];
  for (ssize_t n; (n = ::read(fds[0], buffer, sizeof(buffer))) > 0;) message.append(buffer, static_cast<size_t>(n));
  ::close(fds[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  return message.empty() ? "FAIL the child died without a word" : message;
}

}  // namespace mocap::testing
