#include "capture/ndi/encode.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "capture/ndi/commands.h"
#include "capture/ndi/crc.h"

namespace mocap::ndi {
namespace {

void PutU16(std::vector<uint8_t>& out, uint16_t v) {
  out.push_back(static_cast<uint8_t>(v & 0xFF));
  out.push_back(static_cast<uint8_t>(v >> 8));
}

void PutU32(std::vector<uint8_t>& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
}

void PutF32(std::vector<uint8_t>& out, double v) {
  const float f = static_cast<float>(v);
  uint32_t bits;
  std::memcpy(&bits, &f, sizeof(bits));
  PutU32(out, bits);
}

// Sign and `digits` decimal digits of value/scale, clamped to the field.
std::string SignedField(double value, double scale, int digits) {
  const double limit = std::pow(10.0, digits) - 1;
  const double scaled = std::isfinite(value) ? std::clamp(std::round(value / scale), -limit, limit) : 0.0;
  char text[32];
  std::snprintf(text, sizeof(text), "%c%0*lld", scaled < 0 ? '-' : '+', digits, static_cast<long long>(std::fabs(scaled)));
  return text;
}

}  // namespace

std::string FrameReply(std::string_view text) {
  std::string framed(text);
  framed += Crc16Hex(text);
  framed += '\r';
  return framed;
}

std::string FrameErrorReply(int code) {
  char text[16];
  std::snprintf(text, sizeof(text), "ERROR%02X", code & 0xFF);
  return FrameReply(text);
}

std::vector<uint8_t> EncodeBx(const TrackingReply& reply, uint16_t options) {
  std::vector<uint8_t> body;
  body.push_back(static_cast<uint8_t>(reply.handles.size()));
  for (const HandleReport& h : reply.handles) {
    body.push_back(static_cast<uint8_t>(h.handle));
    body.push_back(static_cast<uint8_t>(h.status));
    if (h.status == HandleStatus::kDisabled) continue;
    if (h.status == HandleStatus::kValid) {
      for (double q : h.q_wxyz) PutF32(body, q);
      for (double t : h.t_mm) PutF32(body, t);
      PutF32(body, h.rms_error_mm);
    }
    PutU32(body, h.port_status);
    PutU32(body, h.frame_number);
    if (options & reply_option::kToolMarkers) {  // §6: count, ceil(n/8) out-of-volume bits (none set), xyz
      body.push_back(static_cast<uint8_t>(h.markers_mm.size()));
      body.insert(body.end(), (h.markers_mm.size() + 7) / 8, 0);
      for (const auto& xyz : h.markers_mm)
        for (double v : xyz) PutF32(body, v);
    }
  }
  PutU16(body, reply.system_status);
  std::vector<uint8_t> frame;
  PutU16(frame, kBxStartSequence);
  PutU16(frame, static_cast<uint16_t>(body.size()));
  PutU16(frame, Crc16(frame));
  frame.insert(frame.end(), body.begin(), body.end());
  PutU16(frame, Crc16(body));
  return frame;
}

std::string EncodeTxText(const TrackingReply& reply) {
  char text[32];
  std::snprintf(text, sizeof(text), "%02X", static_cast<unsigned>(reply.handles.size() & 0xFF));
  std::string out = text;
  for (const HandleReport& h : reply.handles) {
    std::snprintf(text, sizeof(text), "%02X", static_cast<unsigned>(h.handle & 0xFF));
    out += text;
    if (h.status == HandleStatus::kMissing) {
      out += "MISSING";
    } else if (h.status == HandleStatus::kDisabled) {
      out += "DISABLED";
    } else {
      for (double q : h.q_wxyz) out += SignedField(q, 1e-4, 5);
      for (double t : h.t_mm) out += SignedField(t, 1e-2, 6);
      out += SignedField(h.rms_error_mm, 1e-4, 5);
    }
    std::snprintf(text, sizeof(text), "%08X%08X\n", static_cast<unsigned>(h.port_status),
                  static_cast<unsigned>(h.frame_number));
    out += text;
  }
  std::snprintf(text, sizeof(text), "%04X", static_cast<unsigned>(reply.system_status));
  return out + text;
}

}  // namespace mocap::ndi
