#include "capture/ndi/reply.h"

#include <cstring>

#include "capture/ndi/crc.h"
#include "capture/ndi/cursor.h"

namespace mocap::ndi {
namespace {

constexpr std::string_view kCrcMismatch = "CRC mismatch";

struct ErrorText {
  int code;
  std::string_view message;
};

// ndicapi.h error codes (Combined API error replies), plus 0x39 from the reference's §1.
constexpr ErrorText kErrors[] = {
    {0x01, "Invalid command"},
    {0x02, "Command too long"},
    {0x03, "Command too short"},
    {0x04, "Invalid CRC calculated for command"},
    {0x05, "Time-out on command execution"},
    {0x06, "Unable to set up new communication parameters"},
    {0x07, "Incorrect number of command parameters"},
    {0x08, "Invalid port handle selected"},
    {0x09, "Invalid mode selected"},
    {0x0A, "Invalid LED selected"},
    {0x0B, "Invalid LED state selected"},
    {0x0C, "Command is invalid while in the current operating mode"},
    {0x0D, "No tool plugged in the selected port"},
    {0x0E, "Selected port handle not initialised"},
    {0x0F, "Selected port handle not enabled"},
    {0x10, "System not initialised"},
    {0x11, "Failure to stop tracking"},
    {0x12, "Failure to start tracking"},
    {0x13, "Failure to initialise the tool in the port"},
    {0x14, "Invalid position sensor characterisation parameters"},
    {0x15, "Failure to initialise the measurement system"},
    {0x16, "Failure to start diagnostic mode"},
    {0x17, "Failure to stop diagnostic mode"},
    {0x18, "Failure to determine environmental infrared"},
    {0x19, "Failure to read firmware version"},
    {0x1A, "Internal system error"},
    {0x1B, "Failure to initialise for infrared diagnostics"},
    {0x1C, "Failure to set marker firing signature"},
    {0x1D, "Failure to search for SROM IDs"},
    {0x1E, "Failure to read SROM data"},
    {0x1F, "Failure to write SROM data"},
    {0x20, "Failure to select SROM"},
    {0x21, "Failure to perform tool current test"},
    {0x22, "No camera parameters for this wavelength"},
    {0x23, "Command parameter out of range"},
    {0x24, "No camera parameters for this volume"},
    {0x25, "Failure to determine supported features"},
    {0x39, "Permission denied (command needs a master connection)"},
    {0xF1, "Too much environmental infrared"},
    {0xF4, "Failure to erase flash EPROM"},
    {0xF5, "Failure to write flash EPROM"},
    {0xF6, "Failure to read flash EPROM"},
};

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

std::optional<int> ParseCode(std::string_view digits) {
  if (digits.size() != 2) return std::nullopt;
  const int hi = HexValue(digits[0]), lo = HexValue(digits[1]);
  if (hi < 0 || lo < 0) return std::nullopt;
  return hi * 16 + lo;
}

}  // namespace

std::string ParseError::ToString() const { return "byte " + std::to_string(offset) + ": " + message; }

bool IsCrcError(const ParseError& error) { return error.message.find(kCrcMismatch) != std::string::npos; }

std::string_view ErrorCodeMessage(int code) {
  for (const ErrorText& entry : kErrors)
    if (entry.code == code) return entry.message;
  return "unknown error code";
}

std::string DescribeErrorReply(const AsciiReply& reply) {
  return reply.text + " (" + std::string(ErrorCodeMessage(reply.code)) + ")";
}

std::string_view ToString(HandleStatus status) {
  switch (status) {
    case HandleStatus::kValid: return "valid";
    case HandleStatus::kMissing: return "missing";
    case HandleStatus::kDisabled: return "disabled";
  }
  return "unknown";
}

std::string DescribeSystemStatus(uint16_t status) {
  static constexpr std::pair<uint16_t, std::string_view> kBits[] = {
      {system_status::kCommSyncError, "comm sync error"}, {system_status::kTooMuchInfrared, "too much external IR"},
      {system_status::kCommCrcError, "comm CRC error"},   {system_status::kCommRecoverable, "recoverable comm error"},
      {system_status::kHardwareFailure, "hardware failure"}, {system_status::kHardwareChange, "hardware change"},
      {system_status::kPortOccupied, "port occupied"},    {system_status::kPortUnoccupied, "port unoccupied"}};
  std::string text;
  for (const auto& [bit, name] : kBits) {
    if (!(status & bit)) continue;
    if (!text.empty()) text += ", ";
    text += name;
  }
  return text;
}

Parsed<AsciiReply> ParseAsciiReply(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  if (line.size() < 4) return Parsed<AsciiReply>::Fail(0, "reply shorter than its 4-digit CRC");
  const std::string_view text = line.substr(0, line.size() - 4);
  const std::string_view crc_digits = line.substr(line.size() - 4);
  unsigned crc = 0;
  for (size_t i = 0; i < 4; ++i) {
    const int v = HexValue(crc_digits[i]);
    if (v < 0) return Parsed<AsciiReply>::Fail(text.size() + i, "CRC digit is not hex");
    crc = crc * 16 + static_cast<unsigned>(v);
  }
  if (crc != Crc16(text))
    return Parsed<AsciiReply>::Fail(text.size(), std::string(kCrcMismatch) + " (reply says " +
                                                     std::string(crc_digits) + ", text gives " + Crc16Hex(text) + ")");
  AsciiReply reply{ReplyKind::kText, std::string(text), 0};
  for (const auto& [prefix, kind] : {std::pair{std::string_view("ERROR"), ReplyKind::kError},
                                     std::pair{std::string_view("WARNING"), ReplyKind::kWarning}}) {
    if (text.substr(0, prefix.size()) != prefix) continue;
    const std::optional<int> code = ParseCode(text.substr(prefix.size()));
    if (!code) return Parsed<AsciiReply>::Fail(prefix.size(), std::string(prefix) + " without a 2-digit hex code");
    reply.kind = kind;
    reply.code = *code;
  }
  if (text == "RESET") reply.kind = ReplyKind::kReset;
  return {reply, {}};
}

Parsed<std::vector<HandleInfo>> ParsePhsr(std::string_view text) {
  TextCursor cursor(text);
  const std::optional<uint32_t> count = cursor.Hex(2);
  if (!count) return Parsed<std::vector<HandleInfo>>::Fail(cursor.offset(), "PHSR: expected a 2-digit handle count");
  std::vector<HandleInfo> handles;
  for (uint32_t i = 0; i < *count; ++i) {
    const std::optional<uint32_t> handle = cursor.Hex(2);
    const std::optional<uint32_t> status = handle ? cursor.Hex(3) : std::nullopt;
    if (!status) return Parsed<std::vector<HandleInfo>>::Fail(cursor.offset(), "PHSR: truncated handle entry");
    handles.push_back({static_cast<int>(*handle), static_cast<int>(*status)});
  }
  if (!cursor.AtEnd()) return Parsed<std::vector<HandleInfo>>::Fail(cursor.offset(), "PHSR: trailing characters");
  return {handles, {}};
}

Parsed<int> ParseHandleReply(std::string_view text) {
  TextCursor cursor(text);
  const std::optional<uint32_t> handle = cursor.Hex(2);
  if (!handle || !cursor.AtEnd()) return Parsed<int>::Fail(cursor.offset(), "expected a 2-digit hex port handle");
  return {static_cast<int>(*handle), {}};
}

}  // namespace mocap::ndi
