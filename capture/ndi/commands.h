#pragma once
// Command texts of the NDI Combined API (reference ndi-combined-api.md §2-§4) and their framing.
// A command is NAME ':' parameters, then the CRC-16 as 4 hex digits and CR. A command written with a
// space instead of the colon ("APIREV ") is sent without CRC, as NDI's own sample does.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace mocap::ndi {

/// "INIT:" -> "INIT:E3A5\r"; "APIREV " -> "APIREV \r".
std::string FrameCommand(std::string_view command);

/// The reply-option bits of TX/BX (§3). The client asks for 0x0801: transforms and status, also for
/// tools out of volume (reported with port-status bit 0x40 instead of being dropped).
namespace reply_option {
inline constexpr uint16_t kTransforms = 0x0001;
inline constexpr uint16_t kToolAndMarkerInfo = 0x0002;
inline constexpr uint16_t kSingleStray = 0x0004;
inline constexpr uint16_t kToolMarkers = 0x0008;
inline constexpr uint16_t kOutOfVolume = 0x0800;
inline constexpr uint16_t kPassiveStrays = 0x1000;
}  // namespace reply_option

/// PHSR selectors (§3).
enum class HandleQuery : int { kAll = 0, kToBeFreed = 1, kUninitialised = 2, kUnenabled = 3, kEnabled = 4 };

/// PENA tracking priority (§3).
enum class ToolMode : char { kStatic = 'S', kDynamic = 'D', kButtonBox = 'B' };

/// Baud rates the COMM command can select (code 0..7, 'A'); the host UART must match after OKAY.
struct BaudRate {
  int baud = 9600;
  char code = '0';
};
/// Throws InputError when `baud` is not one COMM supports.
BaudRate BaudRateFromBaud(int baud);
/// Throws InputError for an unknown code.
BaudRate BaudRateFromCode(char code);

// Command texts, unframed (pass to FrameCommand or NdiClient::Command).
std::string InitCommand();
std::string ApiRevCommand();
std::string BeepCommand(int count);
std::string CommCommand(const BaudRate& rate, bool handshake = false);  ///< always 8N1
std::string PhsrCommand(HandleQuery query);
std::string PhfCommand(int handle);
/// Passive (wireless) tool whose definition is uploaded with PVWR: "PHRQ:*********1****".
std::string PhrqPassiveCommand();
/// One 64-byte chunk of a tool definition at `address` (a multiple of 64). `chunk` is zero-padded.
std::string PvwrCommand(int handle, int address, std::span<const uint8_t> chunk);
std::string PinitCommand(int handle);
std::string PenaCommand(int handle, ToolMode mode);
std::string TstartCommand();
std::string TstopCommand();
std::string BxCommand(uint16_t options);
std::string TxCommand(uint16_t options);

/// Size of a PVWR chunk in bytes (§3).
inline constexpr int kPvwrChunkBytes = 64;

}  // namespace mocap::ndi
