#pragma once
// A Transport over a POSIX file descriptor (socket or tty); owns and closes the descriptor.
#include <sys/types.h>

#include "capture/ndi/transport.h"

namespace mocap::ndi {

class FdTransport : public Transport {
 public:
  FdTransport(int fd, std::string description) : description_(std::move(description)), fd_(fd) {}
  ~FdTransport() override;
  FdTransport(const FdTransport&) = delete;
  FdTransport& operator=(const FdTransport&) = delete;

  void Write(std::string_view bytes) override;
  size_t Read(std::vector<uint8_t>& out, int timeout_ms) override;
  std::string Describe() const override { return description_; }

 protected:
  int fd() const { return fd_; }
  std::string description_;

 private:
  ssize_t WriteSome(std::string_view bytes);

  int fd_;
  bool is_tty_ = false;  // set on the first ENOTSOCK
};

/// errno as text, for TransportError messages.
std::string ErrnoText(int error);

}  // namespace mocap::ndi
