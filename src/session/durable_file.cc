#include "session/durable_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <system_error>

#include "core/check.h"

namespace mocap {
namespace fs = std::filesystem;

namespace {

[[noreturn]] void ThrowErrno(const fs::path& path, const char* action, int error) {
  throw InputError(path.string(), Str(action, " failed: ", std::strerror(error)));
}

void WriteAll(int fd, std::string_view bytes, const fs::path& path) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      ThrowErrno(path, "write", errno);
    }
    bytes.remove_prefix(static_cast<size_t>(n));
  }
}

}  // namespace

void WriteFileRemovingOnFailure(const fs::path& path, std::string_view contents, bool sync) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) ThrowErrno(path, "open", errno);
  try {
    WriteAll(fd, contents, path);
    if (sync && ::fdatasync(fd) != 0) ThrowErrno(path, "fdatasync", errno);
  } catch (...) {
    ::close(fd);
    ::unlink(path.c_str());
    throw;
  }
  if (::close(fd) != 0) {
    const int error = errno;
    ::unlink(path.c_str());
    ThrowErrno(path, "close", error);
  }
}

void SyncDirectory(const fs::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) ThrowErrno(dir, "open folder", errno);
  const int result = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  if (result != 0 && error != EINVAL) ThrowErrno(dir, "fsync folder", error);
}

void WriteFileAtomically(const fs::path& path, std::string_view contents) {
  const fs::path temp = fs::path(path).concat(".tmp");
  WriteFileRemovingOnFailure(temp, contents, /*sync=*/true);
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::unlink(temp.c_str());
    ThrowErrno(path, "rename", error);
  }
  SyncDirectory(path.parent_path().empty() ? fs::path(".") : path.parent_path());
}

AppendFile::AppendFile(const fs::path& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd_ < 0) ThrowErrno(path, "open", errno);
}

AppendFile::~AppendFile() {
  if (fd_ >= 0) ::close(fd_);
}

void AppendFile::Append(std::string_view bytes) {
  dirty_ = true;
  WriteAll(fd_, bytes, path_);
}

void AppendFile::Sync() {
  if (!dirty_.exchange(false)) return;
  if (::fdatasync(fd_) != 0) ThrowErrno(path_, "fdatasync", errno);
}

bool LinkOrCopyFile(const fs::path& source, const fs::path& path) {
  const fs::path temp = fs::path(path).concat(".tmp");
  std::error_code error;
  fs::create_hard_link(source, temp, error);
  const bool linked = !error;
  if (!linked) {
    fs::remove(temp, error);
    std::ifstream in(source, std::ios::binary);
    if (!in) throw InputError(path.string(), Str("cannot copy ", source.string(), ": cannot open it"));
    const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    if (in.bad()) throw InputError(path.string(), Str("cannot copy ", source.string(), ": read failed"));
    try {
      WriteFileRemovingOnFailure(temp, bytes, false);
    } catch (const InputError& e) {
      throw InputError(path.string(), Str("cannot copy ", source.string(), ": ", e.what()));
    }
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(temp.c_str());
    throw InputError(path.string(), Str("rename failed: ", std::strerror(err)));
  }
  return linked;
}

}  // namespace mocap
