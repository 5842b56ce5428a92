// libFuzzer target for the NDI reply parsers: whatever the bytes, they return a value or a ParseError,
// never crash or read out of bounds (run under AddressSanitizer and UBSan).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "capture/ndi/crc.h"
#include "capture/ndi/reply.h"

namespace {

// Rewrites length and both CRCs of a BX frame so mutated bodies get past the CRC checks and reach the
// field parsing (without this the fuzzer mostly exercises the CRC rejection).
std::vector<uint8_t> WithValidFraming(std::span<const uint8_t> bytes) {
  std::vector<uint8_t> frame(bytes.begin(), bytes.end());
  if (frame.size() < 8 || frame.size() - 8 > 0xFFFF) return frame;
  frame[0] = 0xC4;
  frame[1] = 0xA5;
  const size_t body = frame.size() - 8;
  frame[2] = static_cast<uint8_t>(body & 0xFF);
  frame[3] = static_cast<uint8_t>(body >> 8);
  const uint16_t header_crc = mocap::ndi::Crc16(std::span(frame).subspan(0, 4));
  frame[4] = static_cast<uint8_t>(header_crc & 0xFF);
  frame[5] = static_cast<uint8_t>(header_crc >> 8);
  const uint16_t body_crc = mocap::ndi::Crc16(std::span(frame).subspan(6, body));
  frame[frame.size() - 2] = static_cast<uint8_t>(body_crc & 0xFF);
  frame[frame.size() - 1] = static_cast<uint8_t>(body_crc >> 8);
  return frame;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mocap::ndi;
  if (size == 0) return 0;
  // The first byte picks the reply options (a client could have asked for any of them) and, with its
  // top bit, whether BX framing is repaired first.
  static constexpr uint16_t kOptions[] = {0x0001, 0x0801, 0x0003, 0x0009, 0x1001, 0x100B, 0x0004};
  const uint16_t options = kOptions[data[0] % (sizeof(kOptions) / sizeof(kOptions[0]))];
  const std::vector<uint8_t> repaired =
      (data[0] & 0x80) ? WithValidFraming(std::span(data + 1, size - 1)) : std::vector<uint8_t>(data + 1, data + size);
  const std::span<const uint8_t> bytes(repaired);
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  const Parsed<TrackingReply> bx = ParseBx(bytes, options);
  if (bx.ok()) {
    for (const HandleReport& h : bx.value->handles) (void)ToString(h.status);
  } else if (bx.error.offset > bytes.size()) {
    __builtin_trap();  // an error must point inside (or just past) the reply
  }
  (void)ParseBxHeader(bytes);
  (void)ParseTx(text, options & 0x0801);
  const Parsed<AsciiReply> ascii = ParseAsciiReply(text);
  if (ascii.ok() && ascii.value->kind == ReplyKind::kError) (void)DescribeErrorReply(*ascii.value);
  (void)ParsePhsr(text);
  (void)ParseHandleReply(text);
  (void)DescribeSystemStatus(static_cast<uint16_t>(size));
  return 0;
}
