#include "capture/ndi/link.h"

#include <algorithm>

#include "capture/ndi/commands.h"

namespace mocap::ndi {
namespace {

constexpr int kResyncQuietMs = 20;
constexpr int kResyncMaxMs = 250;

std::string Printable(std::string_view text) {
  std::string out;
  for (char c : text.substr(0, 40)) out += (c >= 32 && c < 127) ? c : '.';
  return text.size() > 40 ? out + "..." : out;
}

}  // namespace

void Link::Fail(ReplyError::Kind kind, int code, const std::string& message) {
  switch (kind) {
    case ReplyError::Kind::kDeviceError: ++counters_.device_errors; break;
    case ReplyError::Kind::kTimeout: ++counters_.timeouts; break;
    case ReplyError::Kind::kCrc: ++counters_.crc_errors; break;
    case ReplyError::Kind::kMalformed: ++counters_.malformed_replies; break;
  }
  if (kind != ReplyError::Kind::kDeviceError) Resync();
  throw ReplyError(kind, code, message);
}

bool Link::Fill(size_t size, Clock::time_point deadline) {
  while (buffer_.size() < size) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return false;
    transport_->Read(buffer_, static_cast<int>(left));
  }
  return true;
}

std::optional<size_t> Link::FillLine(Clock::time_point deadline) {
  size_t searched = 0;
  while (true) {
    const auto cr = std::find(buffer_.begin() + static_cast<std::ptrdiff_t>(searched), buffer_.end(), '\r');
    if (cr != buffer_.end()) return static_cast<size_t>(cr - buffer_.begin());
    searched = buffer_.size();
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return std::nullopt;
    transport_->Read(buffer_, static_cast<int>(left));
  }
}

std::string Link::TakeLine(size_t cr_index) {
  std::string line(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(cr_index));
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(cr_index + 1));
  return line;
}

void Link::Resync() {
  buffer_.clear();
  const auto stop = Clock::now() + std::chrono::milliseconds(kResyncMaxMs);
  while (Clock::now() < stop && transport_->Read(buffer_, kResyncQuietMs) > 0) buffer_.clear();
  buffer_.clear();
}

AsciiReply Link::ReadAscii(std::string_view command, Clock::time_point deadline) {
  const std::optional<size_t> cr = FillLine(deadline);
  if (!cr) Fail(ReplyError::Kind::kTimeout, 0, std::string(command) + ": no reply from the tracker in time");
  const std::string line = TakeLine(*cr);
  const Parsed<AsciiReply> reply = ParseAsciiReply(line);
  if (!reply.ok())
    Fail(IsCrcError(reply.error) ? ReplyError::Kind::kCrc : ReplyError::Kind::kMalformed, 0,
         std::string(command) + ": bad reply '" + Printable(line) + "' at " + reply.error.ToString());
  if (reply.value->kind == ReplyKind::kError)
    Fail(ReplyError::Kind::kDeviceError, reply.value->code,
         std::string(command) + ": tracker replied " + DescribeErrorReply(*reply.value));
  return *reply.value;
}

void Link::Send(std::string_view command) {
  // Request/reply: anything already waiting is a late reply to an exchange that timed out. Dropping
  // it keeps it from being read as the answer to this command.
  while (transport_->Read(buffer_, 0) > 0) {
  }
  buffer_.clear();
  transport_->Write(FrameCommand(command));
}

std::string Link::Command(std::string_view command, int timeout_ms) {
  Send(command);
  return ReadAscii(command, Clock::now() + std::chrono::milliseconds(timeout_ms)).text;
}

TrackingReply Link::Tx(uint16_t options, int timeout_ms) {
  const std::string command = TxCommand(options);
  const std::string text = Command(command, timeout_ms);
  Parsed<TrackingReply> reply = ParseTx(text, options);
  if (!reply.ok()) Fail(ReplyError::Kind::kMalformed, 0, command + ": " + reply.error.ToString());
  return std::move(*reply.value);
}

TrackingReply Link::Bx(uint16_t options, int timeout_ms) {
  const std::string command = BxCommand(options);
  Send(command);
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  if (!Fill(1, deadline)) Fail(ReplyError::Kind::kTimeout, 0, command + ": no reply from the tracker in time");
  if (buffer_[0] != (kBxStartSequence & 0xFF)) {
    ReadAscii(command, deadline);  // an ERRORxx reply throws here
    Fail(ReplyError::Kind::kMalformed, 0, command + ": text reply where a binary frame was expected");
  }
  if (!Fill(kBxHeaderBytes, deadline)) Fail(ReplyError::Kind::kTimeout, 0, command + ": reply header incomplete");
  const Parsed<size_t> size = ParseBxHeader(std::span(buffer_.data(), kBxHeaderBytes));
  if (!size.ok())
    Fail(IsCrcError(size.error) ? ReplyError::Kind::kCrc : ReplyError::Kind::kMalformed, 0,
         command + ": " + size.error.ToString());
  if (!Fill(*size.value, deadline)) Fail(ReplyError::Kind::kTimeout, 0, command + ": reply body incomplete");
  Parsed<TrackingReply> reply = ParseBx(std::span(buffer_.data(), *size.value), options);
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(*size.value));
  if (!reply.ok())
    Fail(IsCrcError(reply.error) ? ReplyError::Kind::kCrc : ReplyError::Kind::kMalformed, 0,
         command + ": " + reply.error.ToString());
  return std::move(*reply.value);
}

std::optional<AsciiReply> Link::ReadUnsolicited(int timeout_ms) {
  const std::optional<size_t> cr = FillLine(Clock::now() + std::chrono::milliseconds(timeout_ms));
  if (!cr) return std::nullopt;
  const Parsed<AsciiReply> reply = ParseAsciiReply(TakeLine(*cr));
  return reply.value;
}

}  // namespace mocap::ndi
