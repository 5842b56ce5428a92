// BX and TX tracking replies (reference ndi-combined-api.md §5, §6).
#include <string>

#include "capture/ndi/commands.h"
#include "capture/ndi/crc.h"
#include "capture/ndi/cursor.h"
#include "capture/ndi/reply.h"

namespace mocap::ndi {
namespace {

using Result = Parsed<TrackingReply>;

constexpr uint16_t kBxSupported = reply_option::kTransforms | reply_option::kToolAndMarkerInfo |
                                  reply_option::kToolMarkers | reply_option::kOutOfVolume |
                                  reply_option::kPassiveStrays;
constexpr uint16_t kTxSupported = reply_option::kTransforms | reply_option::kOutOfVolume;

std::string Hex4(unsigned value) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  std::string text(4, '0');
  for (int i = 3; i >= 0; --i, value >>= 4) text[static_cast<size_t>(i)] = kDigits[value & 0xF];
  return text;
}

// Marker block of options 0x0008 and 0x1000: count, out-of-volume bitmask, count x xyz f32.
bool ReadMarkers(ByteCursor& cursor, std::vector<std::array<double, 3>>& markers) {
  const std::optional<uint8_t> count = cursor.U8();
  if (!count || !cursor.Skip((*count + 7u) / 8u)) return false;
  for (unsigned i = 0; i < *count; ++i) {
    std::array<double, 3> xyz{};
    for (double& v : xyz) {
      const std::optional<float> f = cursor.F32();
      if (!f) return false;
      v = *f;
    }
    markers.push_back(xyz);
  }
  return true;
}

bool ReadBxTransform(ByteCursor& cursor, HandleReport& report) {
  float values[8];
  for (float& v : values) {
    const std::optional<float> f = cursor.F32();
    if (!f) return false;
    v = *f;
  }
  report.q_wxyz = {values[0], values[1], values[2], values[3]};
  report.t_mm = {values[4], values[5], values[6]};
  report.rms_error_mm = values[7];
  report.has_transform = true;
  return true;
}

// One handle of a BX body; returns an error message, empty on success.
std::string ReadBxHandle(ByteCursor& cursor, uint16_t options, HandleReport& report) {
  const std::optional<uint8_t> handle = cursor.U8();
  const std::optional<uint8_t> status = handle ? cursor.U8() : std::nullopt;
  if (!status) return "truncated handle entry";
  report.handle = *handle;
  if (*status != 0x01 && *status != 0x02 && *status != 0x04)
    return "handle status " + std::to_string(*status) + " is none of VALID 1, MISSING 2, DISABLED 4";
  report.status = static_cast<HandleStatus>(*status);
  if (report.status == HandleStatus::kDisabled) return {};  // nothing follows a disabled handle (§6)
  if (options & reply_option::kTransforms) {
    if (report.status == HandleStatus::kValid && !ReadBxTransform(cursor, report)) return "truncated transform";
    const std::optional<uint32_t> port = cursor.U32();
    const std::optional<uint32_t> frame = port ? cursor.U32() : std::nullopt;
    if (!frame) return "truncated port status / frame number";
    report.has_port_status = true;
    report.port_status = *port;
    report.frame_number = *frame;
  }
  if ((options & reply_option::kToolAndMarkerInfo) && !cursor.Skip(11)) return "truncated tool/marker info";
  if ((options & reply_option::kToolMarkers) && !ReadMarkers(cursor, report.markers_mm)) return "truncated markers";
  return {};
}

}  // namespace

Parsed<size_t> ParseBxHeader(std::span<const uint8_t> header) {
  ByteCursor cursor(header);
  const std::optional<uint16_t> start = cursor.U16();
  const std::optional<uint16_t> length = start ? cursor.U16() : std::nullopt;
  const std::optional<uint16_t> crc = length ? cursor.U16() : std::nullopt;
  if (!crc) return Parsed<size_t>::Fail(header.size(), "BX header shorter than 6 bytes");
  if (*start != kBxStartSequence) return Parsed<size_t>::Fail(0, "BX start sequence is not C4 A5");
  if (*crc != Crc16(header.subspan(0, 4)))
    return Parsed<size_t>::Fail(4, "BX header CRC mismatch (frame says " + Hex4(*crc) + ", header gives " +
                                       Hex4(Crc16(header.subspan(0, 4))) + ")");
  return {static_cast<size_t>(*length) + kBxHeaderBytes + 2, {}};
}

Parsed<TrackingReply> ParseBx(std::span<const uint8_t> frame, uint16_t options) {
  if (options & ~kBxSupported) return Result::Fail(0, "BX reply option bits " + Hex4(options & ~kBxSupported) + " are not supported");
  const Parsed<size_t> size = ParseBxHeader(frame.subspan(0, std::min(frame.size(), kBxHeaderBytes)));
  if (!size.ok()) return Result::Fail(size.error.offset, size.error.message);
  if (frame.size() != *size.value)
    return Result::Fail(frame.size(), "BX frame has " + std::to_string(frame.size()) + " bytes, header says " +
                                          std::to_string(*size.value));
  const std::span<const uint8_t> body = frame.subspan(kBxHeaderBytes, *size.value - kBxHeaderBytes - 2);
  const uint16_t body_crc = static_cast<uint16_t>(frame[frame.size() - 2] | (frame[frame.size() - 1] << 8));
  if (body_crc != Crc16(body))
    return Result::Fail(frame.size() - 2, "BX body CRC mismatch (frame says " + Hex4(body_crc) + ", body gives " +
                                              Hex4(Crc16(body)) + ")");
  ByteCursor cursor(body, kBxHeaderBytes);
  const std::optional<uint8_t> count = cursor.U8();
  if (!count) return Result::Fail(cursor.offset(), "BX body is empty");
  TrackingReply reply;
  for (unsigned i = 0; i < *count; ++i) {
    const size_t at = cursor.offset();
    HandleReport report;
    const std::string error = ReadBxHandle(cursor, options, report);
    if (!error.empty()) return Result::Fail(at, "BX handle " + std::to_string(i) + ": " + error);
    reply.handles.push_back(std::move(report));
  }
  if ((options & reply_option::kPassiveStrays) && !ReadMarkers(cursor, reply.passive_strays_mm))
    return Result::Fail(cursor.offset(), "BX passive strays truncated");
  const std::optional<uint16_t> system = cursor.U16();
  if (!system) return Result::Fail(cursor.offset(), "BX body ends before the system status");
  if (cursor.remaining() != 0) return Result::Fail(cursor.offset(), "BX body has bytes after the system status");
  reply.system_status = *system;
  return {std::move(reply), {}};
}

namespace {

bool ReadTxTransform(TextCursor& cursor, HandleReport& report) {
  for (double& q : report.q_wxyz) {
    const std::optional<double> v = cursor.SignedDecimal(5, 1e-4);
    if (!v) return false;
    q = *v;
  }
  for (double& t : report.t_mm) {
    const std::optional<double> v = cursor.SignedDecimal(6, 1e-2);
    if (!v) return false;
    t = *v;
  }
  const std::optional<double> error = cursor.SignedDecimal(5, 1e-4);
  if (!error) return false;
  report.rms_error_mm = *error;
  report.has_transform = true;
  return true;
}

}  // namespace

Parsed<TrackingReply> ParseTx(std::string_view text, uint16_t options) {
  if (options & ~kTxSupported) return Result::Fail(0, "TX reply option bits " + Hex4(options & ~kTxSupported) + " are not supported");
  TextCursor cursor(text);
  const std::optional<uint32_t> count = cursor.Hex(2);
  if (!count) return Result::Fail(0, "TX: expected a 2-digit handle count");
  TrackingReply reply;
  for (uint32_t i = 0; i < *count; ++i) {
    const size_t at = cursor.offset();
    HandleReport report;
    const std::optional<uint32_t> handle = cursor.Hex(2);
    if (!handle) return Result::Fail(at, "TX: expected a 2-digit port handle");
    report.handle = static_cast<int>(*handle);
    if (cursor.Take("UNOCCUPIED")) {
      // An empty port: ndicapi skips it up to the LF.
      cursor.SkipPast('\n');
      continue;
    }
    if (cursor.Take("MISSING")) {
      report.status = HandleStatus::kMissing;
    } else if (cursor.Take("DISABLED")) {
      report.status = HandleStatus::kDisabled;
    } else if (ReadTxTransform(cursor, report)) {
      report.status = HandleStatus::kValid;
    } else {
      return Result::Fail(cursor.offset(), "TX: malformed transform of handle " + std::to_string(*handle));
    }
    const std::optional<uint32_t> port = cursor.Hex(8);
    const std::optional<uint32_t> frame = port ? cursor.Hex(8) : std::nullopt;
    if (!frame) return Result::Fail(cursor.offset(), "TX: expected 8-digit port status and frame number");
    if (!cursor.Take("\n")) return Result::Fail(cursor.offset(), "TX: expected LF after a handle");
    report.has_port_status = true;
    report.port_status = *port;
    report.frame_number = *frame;
    reply.handles.push_back(std::move(report));
  }
  const std::optional<uint32_t> system = cursor.Hex(4);
  if (!system) return Result::Fail(cursor.offset(), "TX: expected a 4-digit system status");
  if (!cursor.AtEnd()) return Result::Fail(cursor.offset(), "TX: trailing characters after the system status");
  reply.system_status = static_cast<uint16_t>(*system);
  return {std::move(reply), {}};
}

}  // namespace mocap::ndi
