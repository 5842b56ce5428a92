// TCP transport (Vega: API on port 8765, reference ndi-combined-api.md §1).
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>

#include "capture/ndi/fd_transport.h"

namespace mocap::ndi {
namespace {

// Non-blocking connect bounded by `timeout_ms`; returns the connected fd or -1 with `error` set.
int ConnectOne(const addrinfo& address, int timeout_ms, std::string& error) {
  const int fd = ::socket(address.ai_family, address.ai_socktype | SOCK_CLOEXEC | SOCK_NONBLOCK, address.ai_protocol);
  if (fd < 0) {
    error = ErrnoText(errno);
    return -1;
  }
  int result = ::connect(fd, address.ai_addr, address.ai_addrlen);
  if (result < 0 && errno == EINPROGRESS) {
    pollfd pfd{fd, POLLOUT, 0};
    result = ::poll(&pfd, 1, timeout_ms);
    if (result == 0) {
      error = "timed out after " + std::to_string(timeout_ms) + " ms";
      ::close(fd);
      return -1;
    }
    int so_error = 0;
    socklen_t length = sizeof(so_error);
    ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &so_error, &length);
    result = so_error == 0 ? 0 : -1;
    errno = so_error;
  }
  if (result < 0) {
    error = ErrnoText(errno);
    ::close(fd);
    return -1;
  }
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));  // replies are small and latency matters
  return fd;
}

}  // namespace

std::unique_ptr<Transport> ConnectTcp(const std::string& host, int port, int timeout_ms) {
  const std::string where = "tcp " + host + ":" + std::to_string(port);
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* addresses = nullptr;
  const int status = ::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &addresses);
  if (status != 0) throw TransportError(where + ": cannot resolve host: " + ::gai_strerror(status));
  std::string error = "no address";
  int fd = -1;
  for (const addrinfo* a = addresses; a != nullptr && fd < 0; a = a->ai_next) fd = ConnectOne(*a, timeout_ms, error);
  ::freeaddrinfo(addresses);
  if (fd < 0) throw TransportError(where + ": connect failed: " + error);
  return std::make_unique<FdTransport>(fd, where);
}

}  // namespace mocap::ndi
