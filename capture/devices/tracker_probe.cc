// Network trackers (NDI Vega and emulators): is anything accepting TCP connections at host:port?
#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "capture/devices/device_scan.h"
#include "core/check.h"

namespace mocap::capture {
namespace {

// Non-blocking connect to one resolved address; "" on success, else why not.
std::string ConnectWithTimeout(const addrinfo& address, int timeout_ms) {
  const int fd = socket(address.ai_family, address.ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, address.ai_protocol);
  if (fd < 0) return std::string("socket: ") + std::strerror(errno);
  std::string why;
  if (connect(fd, address.ai_addr, address.ai_addrlen) < 0) {
    if (errno != EINPROGRESS) {
      why = std::strerror(errno);
    } else {
      pollfd waiting{fd, POLLOUT, 0};
      const int ready = poll(&waiting, 1, timeout_ms);
      int error = 0;
      socklen_t length = sizeof(error);
      if (ready == 0) {
        why = Str("no answer within ", timeout_ms, " ms");
      } else if (ready < 0 || getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length) < 0) {
        why = std::strerror(errno);
      } else if (error != 0) {
        why = std::strerror(error);
      }
    }
  }
  close(fd);
  return why;
}

}  // namespace

TrackerEndpoint ParseTrackerEndpoint(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size())
    throw InputError("--tracker " + text, "expected host:port, e.g. 192.168.1.20:8765");
  TrackerEndpoint endpoint;
  endpoint.host = text.substr(0, colon);
  if (endpoint.host.front() == '[' && endpoint.host.back() == ']') endpoint.host = endpoint.host.substr(1, endpoint.host.size() - 2);
  const std::string port = text.substr(colon + 1);
  if (port.find_first_not_of("0123456789") != std::string::npos || port.size() > 5 || std::stoi(port) < 1 ||
      std::stoi(port) > 65535)
    throw InputError("--tracker " + text, "port '" + port + "' is not a number in 1..65535");
  endpoint.port = std::stoi(port);
  return endpoint;
}

TrackerProbe ProbeTracker(const TrackerEndpoint& endpoint, int timeout_ms) {
  const auto start = std::chrono::steady_clock::now();
  TrackerProbe probe;
  probe.endpoint = endpoint;
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* addresses = nullptr;
  const std::string port = std::to_string(endpoint.port);
  if (const int rc = getaddrinfo(endpoint.host.c_str(), port.c_str(), &hints, &addresses); rc != 0) {
    probe.detail = std::string("cannot resolve host: ") + gai_strerror(rc);
  } else {
    for (const addrinfo* a = addresses; a; a = a->ai_next) {
      probe.detail = ConnectWithTimeout(*a, timeout_ms);
      if (probe.detail.empty()) break;
    }
    freeaddrinfo(addresses);
    probe.reachable = probe.detail.empty();
    if (probe.reachable) probe.detail = "connected";
  }
  probe.connect_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return probe;
}

}  // namespace mocap::capture
