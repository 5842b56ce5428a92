// Writes the fuzz seed corpus: valid replies of every kind the parsers read, each prefixed by the
// option selector byte fuzz_reply.cc uses. Usage: ndi_fuzz_seeds OUT_DIR
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "capture/ndi/encode.h"

namespace {

void Write(const std::filesystem::path& dir, const std::string& name, uint8_t selector, const std::string& bytes) {
  std::ofstream out(dir / name, std::ios::binary);
  out.put(static_cast<char>(selector));
  out << bytes;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mocap::ndi;
  if (argc != 2) {
    std::cerr << "usage: ndi_fuzz_seeds OUT_DIR\n";
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  TrackingReply reply;
  HandleReport valid;
  valid.handle = 0x0A;
  valid.status = HandleStatus::kValid;
  valid.has_transform = true;
  valid.q_wxyz = {0.7071, 0, 0.7071, 0};
  valid.t_mm = {10.5, -20.25, -1500};
  valid.rms_error_mm = 0.12;
  valid.port_status = 0x31;
  valid.frame_number = 123456;
  HandleReport missing = valid;
  missing.handle = 0x0B;
  missing.status = HandleStatus::kMissing;
  missing.has_transform = false;
  HandleReport disabled;
  disabled.handle = 0x0C;
  disabled.status = HandleStatus::kDisabled;
  reply.handles = {valid, missing, disabled};
  reply.system_status = 0x42;
  const std::vector<uint8_t> bx = EncodeBx(reply);
  Write(dir, "bx_three_handles", 0, std::string(bx.begin(), bx.end()));
  Write(dir, "bx_three_handles_0801", 1, std::string(bx.begin(), bx.end()));
  reply.handles = {valid};
  const std::vector<uint8_t> bx_one = EncodeBx(reply);
  Write(dir, "bx_one_handle", 1, std::string(bx_one.begin(), bx_one.end()));
  Write(dir, "bx_three_handles_repaired", 0x81, std::string(bx.begin(), bx.end()));
  reply.handles = {valid, missing, disabled};
  reply.handles[2].has_port_status = true;
  Write(dir, "tx_three_handles", 0, EncodeTxText(reply));
  Write(dir, "tx_unoccupied", 0, "020AUNOCCUPIED00000000\n0BMISSING000000310000000A\n0000");
  Write(dir, "ascii_okay", 0, FrameReply("OKAY"));
  Write(dir, "ascii_error", 0, FrameErrorReply(0x0D));
  Write(dir, "ascii_reset", 0, FrameReply("RESET"));
  Write(dir, "phsr", 0, "030A0310B0010C031");
  Write(dir, "handle", 0, "0A");
  return 0;
}
