#pragma once
// Byte transports to an NDI tracker behind one interface (reference ndi-combined-api.md §1):
// TCP (Vega, API port 8765) and serial (Polaris/Aurora over RS-232 or USB-serial, 8N1).
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace mocap::ndi {

/// The connection failed or was closed (an expected outcome the client recovers from by reconnecting).
class TransportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Transport {
 public:
  virtual ~Transport() = default;
  /// Writes all of `bytes`. Throws TransportError when the connection is gone.
  virtual void Write(std::string_view bytes) = 0;
  /// Appends the bytes that arrive within `timeout_ms` to `out` (returns as soon as some arrived);
  /// returns how many were appended (0 at the timeout). Throws TransportError when the peer closed.
  virtual size_t Read(std::vector<uint8_t>& out, int timeout_ms) = 0;
  /// Serial only: a BREAK, which resets the tracker to 9600 baud (it answers "RESETBE6F").
  virtual void SendBreak() {}
  /// Serial only: switches the host UART (after the tracker acknowledged COMM).
  virtual void SetBaudRate(int baud);
  virtual bool is_serial() const { return false; }
  /// "tcp 127.0.0.1:8765", "serial /dev/ttyUSB0 @ 9600".
  virtual std::string Describe() const = 0;
};

/// Connects to host:port, giving up after `timeout_ms`. Throws TransportError.
std::unique_ptr<Transport> ConnectTcp(const std::string& host, int port, int timeout_ms);
/// Opens a serial device raw, 8N1, no handshake, at `baud`. Throws TransportError.
std::unique_ptr<Transport> OpenSerial(const std::string& device, int baud);

}  // namespace mocap::ndi
