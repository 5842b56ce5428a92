#pragma once
// Parsers for NDI Combined API replies (reference ndi-combined-api.md §2, §5-§7). They never trust the
// bytes: every read is bounds-checked, and a malformed reply yields a ParseError with the byte offset
// instead of a crash. The parsers keep NDI's units (mm, scalar-first quaternion); conversion to the
// project's types happens in convert.h.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mocap::ndi {

struct ParseError {
  size_t offset = 0;    ///< byte offset into the reply where parsing failed
  std::string message;  ///< what was wrong there
  std::string ToString() const;
};

/// A parse result: `value` when it parsed, `error` otherwise.
template <typename T>
struct Parsed {
  std::optional<T> value;
  ParseError error;
  bool ok() const { return value.has_value(); }
  static Parsed Fail(size_t offset, std::string message) { return {std::nullopt, {offset, std::move(message)}}; }
};

enum class ReplyKind : uint8_t { kText, kError, kWarning, kReset };

/// An ASCII reply with its CRC checked and removed.
struct AsciiReply {
  ReplyKind kind = ReplyKind::kText;
  std::string text;  ///< the reply without CRC and CR ("OKAY", "ERROR0D", "0301A001", ...)
  int code = 0;      ///< the hex code of ERRORxx / WARNINGxx
};

/// Parses one ASCII reply line (the trailing CR is optional): text, 4 hex CRC. Fails on a short line,
/// non-hex CRC or a CRC mismatch ("CRC mismatch" in the message: the client counts those).
Parsed<AsciiReply> ParseAsciiReply(std::string_view line);
/// True when `error` came from a CRC check (header, body or ASCII).
bool IsCrcError(const ParseError& error);

/// What an NDI error code means ("No tool plugged in the selected port"); "unknown error code" if unknown.
std::string_view ErrorCodeMessage(int code);
/// "ERROR0D (No tool plugged in the selected port)".
std::string DescribeErrorReply(const AsciiReply& reply);

/// One entry of a PHSR reply: a port handle and its 3 hex status digits.
struct HandleInfo {
  int handle = 0;
  int status = 0;
};
Parsed<std::vector<HandleInfo>> ParsePhsr(std::string_view text);
/// A reply that is just a 2 hex digit port handle (PHRQ).
Parsed<int> ParseHandleReply(std::string_view text);

/// Per-handle status in BX (and its TX equivalent).
enum class HandleStatus : uint8_t { kValid = 0x01, kMissing = 0x02, kDisabled = 0x04 };
std::string_view ToString(HandleStatus status);

/// Port-status bits (§7).
namespace port_status {
inline constexpr uint32_t kToolInPort = 0x0001;
inline constexpr uint32_t kInitialised = 0x0010;
inline constexpr uint32_t kEnabled = 0x0020;
inline constexpr uint32_t kOutOfVolume = 0x0040;
inline constexpr uint32_t kPartiallyInVolume = 0x0080;
}  // namespace port_status

/// System-status bits (§7).
namespace system_status {
inline constexpr uint16_t kCommSyncError = 0x01;
inline constexpr uint16_t kTooMuchInfrared = 0x02;
inline constexpr uint16_t kCommCrcError = 0x04;
inline constexpr uint16_t kCommRecoverable = 0x08;
inline constexpr uint16_t kHardwareFailure = 0x10;
inline constexpr uint16_t kHardwareChange = 0x20;
inline constexpr uint16_t kPortOccupied = 0x40;
inline constexpr uint16_t kPortUnoccupied = 0x80;
}  // namespace system_status
/// "too much external IR, port occupied" (empty for 0).
std::string DescribeSystemStatus(uint16_t status);

/// One handle of a TX/BX reply, in NDI units.
struct HandleReport {
  int handle = 0;
  HandleStatus status = HandleStatus::kMissing;
  bool has_transform = false;             ///< VALID (BX/TX), or reported out of volume with 0x0800
  std::array<double, 4> q_wxyz{1, 0, 0, 0};  ///< scalar first, as sent (not normalised)
  std::array<double, 3> t_mm{0, 0, 0};    ///< position in the position-sensor frame, mm
  double rms_error_mm = 0;                ///< RMS fit error of the tool's markers, mm
  bool has_port_status = false;           ///< false for DISABLED in BX (nothing follows the status)
  uint32_t port_status = 0;
  uint32_t frame_number = 0;
  std::vector<std::array<double, 3>> markers_mm;  ///< option 0x0008
};

struct TrackingReply {
  std::vector<HandleReport> handles;
  std::vector<std::array<double, 3>> passive_strays_mm;  ///< option 0x1000
  uint16_t system_status = 0;
};

/// BX framing (§6): 6-byte header (0xA5C4, body length, header CRC), body, 2-byte body CRC.
inline constexpr size_t kBxHeaderBytes = 6;
inline constexpr uint16_t kBxStartSequence = 0xA5C4;
/// From the first 6 bytes, the whole frame's size (body + 8), after checking the start sequence and
/// the header CRC.
Parsed<size_t> ParseBxHeader(std::span<const uint8_t> header);
/// Parses a whole BX frame requested with `options`. Supported option bits: 0x0001, 0x0002, 0x0008,
/// 0x0800, 0x1000 (0x0004 single stray is refused: its layout is not pinned down).
Parsed<TrackingReply> ParseBx(std::span<const uint8_t> frame, uint16_t options);
/// Parses the text of a TX reply (CRC already removed by ParseAsciiReply). Supported option bits:
/// 0x0001 and 0x0800.
Parsed<TrackingReply> ParseTx(std::string_view text, uint16_t options);

}  // namespace mocap::ndi
