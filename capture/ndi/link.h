#pragma once
// One command/reply exchange at a time over a Transport (the Combined API is strictly request/reply):
// frames the command, reads the reply (ASCII up to CR, or a binary BX frame), checks its CRC, and
// resynchronises after a damaged reply by discarding what is left of it.
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "capture/ndi/reply.h"
#include "capture/ndi/transport.h"

namespace mocap::ndi {

/// The tracker answered ERRORxx, or a reply could not be read (timeout, CRC, parse): the message says
/// which command, what came back and what it means.
class ReplyError : public std::runtime_error {
 public:
  enum class Kind { kDeviceError, kTimeout, kCrc, kMalformed };
  ReplyError(Kind kind, int code, const std::string& message) : std::runtime_error(message), kind_(kind), code_(code) {}
  Kind kind() const { return kind_; }
  int code() const { return code_; }  ///< the ERRORxx code for kDeviceError

 private:
  Kind kind_;
  int code_;
};

struct LinkCounters {
  uint64_t crc_errors = 0;
  uint64_t malformed_replies = 0;
  uint64_t timeouts = 0;
  uint64_t device_errors = 0;
};

class Link {
 public:
  explicit Link(std::unique_ptr<Transport> transport) : transport_(std::move(transport)) {}

  /// Sends `command` (unframed, e.g. "PINIT:0A") and returns the reply text (CRC removed).
  /// Throws ReplyError (ERRORxx, timeout, CRC, malformed) or TransportError.
  std::string Command(std::string_view command, int timeout_ms);
  /// Sends BX with `options` and parses the binary reply; throws as Command does.
  TrackingReply Bx(uint16_t options, int timeout_ms);
  /// Sends TX with `options` and parses the ASCII reply; throws as Command does.
  TrackingReply Tx(uint16_t options, int timeout_ms);
  /// Reads one unsolicited ASCII line (RESET after a serial break); nullopt at timeout.
  std::optional<AsciiReply> ReadUnsolicited(int timeout_ms);

  Transport& transport() { return *transport_; }
  const LinkCounters& counters() const { return counters_; }

 private:
  using Clock = std::chrono::steady_clock;
  void Send(std::string_view command);
  /// Reads until `size` bytes are buffered; false at the deadline.
  bool Fill(size_t size, Clock::time_point deadline);
  /// Reads until a CR is buffered; returns its index or nullopt at the deadline.
  std::optional<size_t> FillLine(Clock::time_point deadline);
  std::string TakeLine(size_t cr_index);
  AsciiReply ReadAscii(std::string_view command, Clock::time_point deadline);
  /// Discards buffered bytes and whatever arrives until the line is quiet, after a damaged reply.
  void Resync();
  [[noreturn]] void Fail(ReplyError::Kind kind, int code, const std::string& message);

  std::unique_ptr<Transport> transport_;
  std::vector<uint8_t> buffer_;
  LinkCounters counters_;
};

}  // namespace mocap::ndi
