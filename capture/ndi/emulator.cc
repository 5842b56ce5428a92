#include "capture/ndi/emulator.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>

#include "capture/ndi/client.h"
#include "capture/ndi/encode.h"
#include "core/check.h"
#include "core/log.h"

namespace mocap::ndi {
namespace {

constexpr int kPollMs = 50;
constexpr size_t kMaxCommandBytes = 4096;
constexpr int kCommandTooLong = 0x02;

uint64_t NextRandom(uint64_t& state) {  // xorshift64*
  state ^= state >> 12;
  state ^= state << 25;
  state ^= state >> 27;
  return state * 2685821657736338717ULL;
}

bool WriteAll(int fd, const std::string& bytes) {
  size_t written = 0;
  while (written < bytes.size()) {
    // MSG_NOSIGNAL: a client that hung up must end this connection, not the process (SIGPIPE);
    // a pseudo-terminal (the serial path) is not a socket and takes write().
    ssize_t n = ::send(fd, bytes.data() + written, bytes.size() - written, MSG_NOSIGNAL);
    if (n < 0 && errno == ENOTSOCK) n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) {
      pollfd pfd{fd, POLLOUT, 0};
      ::poll(&pfd, 1, kPollMs);
      continue;
    }
    if (n <= 0) return false;
    written += static_cast<size_t>(n);
  }
  return true;
}

}  // namespace

void EmulatorOptions::check() const {
  if (port < 0 || port > 65535) throw InputError("emulator port", Str(port, " is not a TCP port"));
  if (!(latency_ms >= 0 && latency_ms <= 10000)) throw InputError("emulator latency", Str(latency_ms, " ms is not in [0, 10000]"));
  if (!(corrupt >= 0 && corrupt <= 1)) throw InputError("emulator corrupt", Str(corrupt, " is not a probability"));
  tracker.check();
}

Emulator::Emulator(EmulatorOptions options, std::shared_ptr<const TrajectorySource> trajectory)
    : options_(std::move(options)), trajectory_(std::move(trajectory)), model_(options_.tracker, trajectory_) {
  options_.check();
  start_ns_ = MonotonicNowNs();
}

Emulator::~Emulator() { Stop(); }

double Emulator::Elapsed() const { return static_cast<double>(MonotonicNowNs() - start_ns_) * 1e-9; }

EmulatorStats Emulator::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void Emulator::Start() {
  const std::string where = options_.bind + ":" + std::to_string(options_.port);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(options_.port));
  if (::inet_pton(AF_INET, options_.bind.c_str(), &address.sin_addr) != 1)
    throw InputError(where, "bind address is not an IPv4 address");
  listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const int one = 1;
  ::setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  if (::bind(listen_fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0 || ::listen(listen_fd_, 4) != 0) {
    const std::string error = std::strerror(errno);
    ::close(listen_fd_);
    listen_fd_ = -1;
    throw InputError(where, "cannot listen: " + error + " (another tracker emulator running? try --port 0)");
  }
  socklen_t length = sizeof(address);
  ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&address), &length);
  port_ = ntohs(address.sin_port);
  start_ns_ = MonotonicNowNs();
  std::lock_guard lock(mutex_);
  threads_.emplace_back([this] { AcceptLoop(); });
}

void Emulator::ServeFd(int fd) {
  std::lock_guard lock(mutex_);
  threads_.emplace_back([this, fd] { Serve(fd, false); });
}

void Emulator::AcceptLoop() {
  while (!stop_) {
    pollfd pfd{listen_fd_, POLLIN, 0};
    if (::poll(&pfd, 1, kPollMs) <= 0) continue;
    const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (fd < 0) continue;
    const int one = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    std::lock_guard lock(mutex_);
    if (stop_) {
      ::close(fd);
      break;
    }
    ++stats_.connections;
    connection_fds_.push_back(fd);
    threads_.emplace_back([this, fd] { Serve(fd, true); });
  }
}

void Emulator::Serve(int fd, bool is_socket) {
  EmulatedTracker tracker(options_.tracker, trajectory_, clock_);
  uint64_t rng_state = options_.tracker.seed * 0x9E3779B97F4A7C15ULL + static_cast<uint64_t>(fd) + 1;
  std::string pending;
  bool logged_end = false;
  while (!stop_) {
    pollfd pfd{fd, POLLIN, 0};
    const int ready = ::poll(&pfd, 1, kPollMs);
    if (ready <= 0) continue;
    char buffer[4096];
    const ssize_t n = (pfd.revents & POLLIN) ? ::read(fd, buffer, sizeof(buffer)) : 0;
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n <= 0) {  // closed, hung up or failed
      if (is_socket) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));  // pty slave closed: wait for it to reopen
      continue;
    }
    pending.append(buffer, static_cast<size_t>(n));
    for (size_t cr; (cr = pending.find('\r')) != std::string::npos;) {
      EmulatorReply reply = tracker.Handle(std::string_view(pending).substr(0, cr), Elapsed());
      pending.erase(0, cr + 1);
      NotePastEnd(reply, logged_end);
      Reply(fd, std::move(reply), rng_state);
    }
    if (pending.size() > kMaxCommandBytes) {
      pending.clear();
      Reply(fd, EmulatorReply{FrameErrorReply(kCommandTooLong)}, rng_state);
    }
  }
  if (!is_socket) return;
  std::lock_guard lock(mutex_);
  connection_fds_.erase(std::remove(connection_fds_.begin(), connection_fds_.end(), fd), connection_fds_.end());
  ::close(fd);
}

// Once per connection: the replay ran out, and every body is MISSING from now on.
void Emulator::NotePastEnd(const EmulatorReply& reply, bool& logged) const {
  if (!reply.past_end || logged || !options_.log_replay_end) return;
  logged = true;
  const uint32_t frame = reply.served.handles.empty() ? 0 : reply.served.handles.front().frame_number;
  Log().warn("NDI emulator: the replayed recording ended at tracking time {:.2f} s (frame {}): every body is MISSING "
             "from now on; a client that stops tracking (TSTOP: the daemon exits) and starts again hears it from the start",
             trajectory_->end_s().value_or(0.0), frame);
}

void Emulator::Reply(int fd, EmulatorReply reply, uint64_t& rng_state) {
  bool corrupted = false;
  if (reply.tracking_data) {
    if (options_.latency_ms > 0) std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(options_.latency_ms));
    const double draw = static_cast<double>(NextRandom(rng_state) >> 11) * 0x1.0p-53;
    if (draw < options_.corrupt && !reply.bytes.empty()) {
      const size_t at = NextRandom(rng_state) % reply.bytes.size();
      reply.bytes[at] = static_cast<char>(reply.bytes[at] ^ static_cast<char>(1 + NextRandom(rng_state) % 255));
      corrupted = true;
    }
  }
  {
    std::lock_guard lock(mutex_);
    ++stats_.commands;
    stats_.tracking_replies += reply.tracking_data;
    stats_.error_replies += reply.bytes.rfind("ERROR", 0) == 0;
    stats_.corrupted_replies += corrupted;
    stats_.past_end_replies += reply.past_end;
    if (reply.new_baud) stats_.last_baud = reply.new_baud;
  }
  if (reply.tracking_data && on_served_) on_served_(reply.served, corrupted);
  WriteAll(fd, reply.bytes);
}

void Emulator::Stop() {
  stop_ = true;
  {
    std::lock_guard lock(mutex_);
    for (int fd : connection_fds_) ::shutdown(fd, SHUT_RDWR);
  }
  std::vector<std::thread> threads;
  {
    std::lock_guard lock(mutex_);
    threads.swap(threads_);
  }
  for (std::thread& thread : threads) thread.join();
  if (listen_fd_ >= 0) ::close(listen_fd_);
  listen_fd_ = -1;
}

}  // namespace mocap::ndi
