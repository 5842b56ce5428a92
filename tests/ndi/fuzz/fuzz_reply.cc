// libFuzzer target for the NDI reply parsers: whatever the bytes, they return a value or a ParseError,
// never crash or read out of bounds (run under AddressSanitizer and UBSan).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "capture/ndi/reply.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mocap::ndi;
  if (size == 0) return 0;
  // The first byte picks the reply options, as a client could have asked for any of them.
  static constexpr uint16_t kOptions[] = {0x0001, 0x0801, 0x0003, 0x0009, 0x1001, 0x100B, 0x0004};
  const uint16_t options = kOptions[data[0] % (sizeof(kOptions) / sizeof(kOptions[0]))];
  const std::span<const uint8_t> bytes(data + 1, size - 1);
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
