#include "capture/ndi/fd_transport.h"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace mocap::ndi {

std::string ErrnoText(int error) { return std::strerror(error); }

void Transport::SetBaudRate(int) { throw TransportError(Describe() + ": not a serial port, cannot change baud rate"); }

FdTransport::~FdTransport() {
  if (fd_ >= 0) ::close(fd_);
}

// A tracker that closes its socket (restarted, unplugged from the network) must surface as a
// TransportError the client reconnects after, not as SIGPIPE ending the recording: sockets are
// written with MSG_NOSIGNAL; a tty (ENOTSOCK) with write().
ssize_t FdTransport::WriteSome(std::string_view bytes) {
  if (!is_tty_) {
    const ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (n >= 0 || errno != ENOTSOCK) return n;
    is_tty_ = true;
  }
  return ::write(fd_, bytes.data(), bytes.size());
}

void FdTransport::Write(std::string_view bytes) {
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = WriteSome(bytes.substr(written));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EAGAIN) {
      pollfd pfd{fd_, POLLOUT, 0};
      ::poll(&pfd, 1, 100);
      continue;
    }
    if (n <= 0) throw TransportError(description_ + ": write failed: " + ErrnoText(errno));
    written += static_cast<size_t>(n);
  }
}

size_t FdTransport::Read(std::vector<uint8_t>& out, int timeout_ms) {
  pollfd pfd{fd_, POLLIN, 0};
  const int ready = ::poll(&pfd, 1, timeout_ms);
  if (ready < 0 && errno == EINTR) return 0;
  if (ready < 0) throw TransportError(description_ + ": poll failed: " + ErrnoText(errno));
  if (ready == 0) return 0;
  uint8_t buffer[4096];
  const ssize_t n = ::read(fd_, buffer, sizeof(buffer));
  if (n < 0 && (errno == EINTR || errno == EAGAIN)) return 0;
  if (n < 0) throw TransportError(description_ + ": read failed: " + ErrnoText(errno));
  if (n == 0) throw TransportError(description_ + ": connection closed by the tracker");
  out.insert(out.end(), buffer, buffer + n);
  return static_cast<size_t>(n);
}

}  // namespace mocap::ndi
