#pragma once
// CRC-16 of the NDI Combined API (reference ndi-combined-api.md §2): CRC-16/ARC, polynomial
// x^16+x^15+x^2+1 (0x8005, reflected 0xA001), init 0, reflected in/out, no final xor.
// ASCII commands and replies carry it as 4 upper-case hex digits before the CR; binary replies (BX)
// carry it as a little-endian u16 for the header (bytes 0-3) and for the body.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace mocap::ndi {

/// CRC-16/ARC of `bytes`, continuing from `crc` (0 for a fresh computation).
uint16_t Crc16(std::span<const uint8_t> bytes, uint16_t crc = 0);
uint16_t Crc16(std::string_view text, uint16_t crc = 0);

/// The 4 upper-case hex digits NDI appends to ASCII commands and replies.
std::string Crc16Hex(std::string_view text);

}  // namespace mocap::ndi
