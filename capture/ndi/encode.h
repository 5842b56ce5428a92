#pragma once
// Writers for the replies the parsers read: the emulator answers with them, and tests and the fuzz
// seed corpus build valid replies from them. Layouts as in reference ndi-combined-api.md §5, §6.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "capture/ndi/reply.h"

namespace mocap::ndi {

/// ASCII reply on the wire: text, 4 hex CRC, CR.
std::string FrameReply(std::string_view text);
/// "ERRORxx" framed, for an error code.
std::string FrameErrorReply(int code);

/// A BX frame (header, body, CRC) for option 0x0001 (with or without 0x0800, 0x0008): per handle its
/// status, the transform when has_transform, port status and frame number unless DISABLED, with 0x0008
/// its markers (count, out-of-volume bitmask, xyz f32 in mm); then system status.
std::vector<uint8_t> EncodeBx(const TrackingReply& reply, uint16_t options = 0x0801);
/// The text of a TX reply for option 0x0001 (CRC not included). Values are rounded to TX precision
/// (1e-4 for quaternion and error, 0.01 mm for translation) and clamped to the field widths.
std::string EncodeTxText(const TrackingReply& reply);

}  // namespace mocap::ndi
