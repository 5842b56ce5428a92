#include "capture/ndi/commands.h"

#include <array>
#include <cstdio>

#include "capture/ndi/crc.h"
#include "core/check.h"

namespace mocap::ndi {
namespace {

std::string Format(const char* format, auto... args) {
  char text[64];
  std::snprintf(text, sizeof(text), format, args...);
  return text;
}

constexpr std::array<BaudRate, 9> kBaudRates = {{{9600, '0'}, {14400, '1'}, {19200, '2'}, {38400, '3'},
                                                  {57600, '4'}, {115200, '5'}, {921600, '6'},
                                                  {1228739, '7'}, {230400, 'A'}}};

}  // namespace

std::string FrameCommand(std::string_view command) {
  std::string framed(command);
  const size_t name_end = command.find_first_of(": ");
  if (name_end != std::string_view::npos && command[name_end] == ':') framed += Crc16Hex(command);
  framed += '\r';
  return framed;
}

BaudRate BaudRateFromBaud(int baud) {
  for (const BaudRate& rate : kBaudRates)
    if (rate.baud == baud) return rate;
  throw InputError("serial baud rate", Str(baud, " is not one the COMM command supports (9600, 14400, 19200, "
                                              "38400, 57600, 115200, 230400, 921600, 1228739)"));
}

BaudRate BaudRateFromCode(char code) {
  for (const BaudRate& rate : kBaudRates)
    if (rate.code == code) return rate;
  throw InputError("COMM", Str("unknown baud code '", code, "'"));
}

std::string InitCommand() { return "INIT:"; }
std::string ApiRevCommand() { return "APIREV "; }
std::string BeepCommand(int count) { return Format("BEEP:%d", count); }
std::string CommCommand(const BaudRate& rate, bool handshake) {
  return Format("COMM:%c000%d", rate.code, handshake ? 1 : 0);
}
std::string PhsrCommand(HandleQuery query) { return Format("PHSR:%02X", static_cast<int>(query)); }
std::string PhfCommand(int handle) { return Format("PHF:%02X", handle); }
std::string PhrqPassiveCommand() { return "PHRQ:*********1****"; }
std::string PinitCommand(int handle) { return Format("PINIT:%02X", handle); }
std::string PenaCommand(int handle, ToolMode mode) { return Format("PENA:%02X%c", handle, static_cast<char>(mode)); }
std::string TstartCommand() { return "TSTART:"; }
std::string TstopCommand() { return "TSTOP:"; }
std::string BxCommand(uint16_t options) { return Format("BX:%04X", static_cast<unsigned>(options)); }
std::string TxCommand(uint16_t options) { return Format("TX:%04X", static_cast<unsigned>(options)); }

std::string PvwrCommand(int handle, int address, std::span<const uint8_t> chunk) {
  MOCAP_CHECK(address % kPvwrChunkBytes == 0 && chunk.size() <= kPvwrChunkBytes, "PVWR chunk ", address);
  std::string command = Format("PVWR:%02X%04X", handle, address);
  for (int i = 0; i < kPvwrChunkBytes; ++i) {
    const unsigned byte = i < static_cast<int>(chunk.size()) ? chunk[static_cast<size_t>(i)] : 0u;
    command += Format("%02X", byte);
  }
  return command;
}

}  // namespace mocap::ndi
