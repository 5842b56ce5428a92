// Serial transport (reference ndi-combined-api.md §1): raw 8N1, no handshake; a BREAK resets the
// tracker to 9600 baud; after COMM is acknowledged the host switches its UART to the new rate.
#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>

#include "capture/ndi/fd_transport.h"

namespace mocap::ndi {
namespace {

speed_t SpeedConstant(int baud) {
  switch (baud) {
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 921600: return B921600;
    default: return B0;  // 14400 and 1228739 have no termios constant on Linux
  }
}

class SerialTransport : public FdTransport {
 public:
  SerialTransport(int fd, std::string device, int baud)
      : FdTransport(fd, "serial " + device + " @ " + std::to_string(baud)), device_(std::move(device)) {
    SetBaudRate(baud);
  }
  void SendBreak() override {
    ::tcsendbreak(fd(), 0);
    ::tcflush(fd(), TCIOFLUSH);
  }
  void SetBaudRate(int baud) override {
    const speed_t speed = SpeedConstant(baud);
    if (speed == B0) throw TransportError("serial " + device_ + ": baud " + std::to_string(baud) + " is not supported on this host");
    termios tio{};
    if (::tcgetattr(fd(), &tio) != 0) throw TransportError("serial " + device_ + ": not a terminal: " + ErrnoText(errno));
    ::cfmakeraw(&tio);
    tio.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | PARENB | CRTSCTS | CSIZE);
    tio.c_cflag |= CS8 | CLOCAL | CREAD;
    tio.c_cc[VMIN] = 0;
    tio.c_cc[VTIME] = 0;
    ::cfsetispeed(&tio, speed);
    ::cfsetospeed(&tio, speed);
    if (::tcsetattr(fd(), TCSANOW, &tio) != 0)
      throw TransportError("serial " + device_ + ": cannot set 8N1 @ " + std::to_string(baud) + ": " + ErrnoText(errno));
    description_ = "serial " + device_ + " @ " + std::to_string(baud);
  }
  bool is_serial() const override { return true; }

 private:
  std::string device_;
};

}  // namespace

std::unique_ptr<Transport> OpenSerial(const std::string& device, int baud) {
  const int fd = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw TransportError("serial " + device + ": cannot open: " + ErrnoText(errno));
  return std::make_unique<SerialTransport>(fd, device, baud);  // the base closes fd if this throws
}

}  // namespace mocap::ndi
