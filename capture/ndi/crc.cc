#include "capture/ndi/crc.h"

#include <array>
#include <cstdio>

namespace mocap::ndi {
namespace {

// Byte-wise table for the reflected polynomial 0xA001.
constexpr std::array<uint16_t, 256> MakeTable() {
  std::array<uint16_t, 256> table{};
  for (unsigned i = 0; i < 256; ++i) {
    uint16_t crc = static_cast<uint16_t>(i);
    for (int bit = 0; bit < 8; ++bit) crc = (crc & 1u) ? static_cast<uint16_t>((crc >> 1) ^ 0xA001u) : static_cast<uint16_t>(crc >> 1);
    table[i] = crc;
  }
  return table;
}

constexpr std::array<uint16_t, 256> kTable = MakeTable();

}  // namespace

uint16_t Crc16(std::span<const uint8_t> bytes, uint16_t crc) {
  for (uint8_t byte : bytes) crc = static_cast<uint16_t>((crc >> 8) ^ kTable[(crc ^ byte) & 0xFFu]);
  return crc;
}

uint16_t Crc16(std::string_view text, uint16_t crc) {
  return Crc16(std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()), crc);
}

std::string Crc16Hex(std::string_view text) {
  char hex[8];
  std::snprintf(hex, sizeof(hex), "%04X", static_cast<unsigned>(Crc16(text)));
  return hex;
}

}  // namespace mocap::ndi
