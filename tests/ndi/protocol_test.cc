// CRC, command framing and reply parsing against reference ndi-combined-api.md §2, §5, §6.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "capture/ndi/commands.h"
#include "capture/ndi/crc.h"
#include "capture/ndi/encode.h"
#include "capture/ndi/reply.h"
#include "core/check.h"

namespace mocap::ndi {
namespace {

// §6 worked example: three handles (VALID, MISSING, DISABLED), 65 bytes.
const std::vector<uint8_t> kBxExample = {
    0xc4, 0xa5, 0x39, 0x00, 0x3f, 0x43, 0x03, 0x0a, 0x01, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x28, 0x41, 0x00, 0x00, 0xa2, 0xc1, 0x00,
    0x80, 0xbb, 0xc4, 0x8f, 0xc2, 0xf5, 0x3d, 0x31, 0x00, 0x00, 0x00, 0x40, 0xe2, 0x01, 0x00, 0x0b, 0x02,
    0x31, 0x00, 0x00, 0x00, 0x40, 0xe2, 0x01, 0x00, 0x0c, 0x04, 0x00, 0x00, 0x25, 0x85};

TEST(NdiCrc, MatchesReferenceVectors) {
  const std::pair<const char*, uint16_t> vectors[] = {
      {"123456789", 0xBB3D}, {"RESET", 0xBE6F},    {"INIT:", 0xE3A5},      {"OKAY", 0xA896},
      {"VER:0", 0x65EE},     {"TSTART:", 0x5423},  {"TSTOP:", 0x2C14},     {"BX:0801", 0x00EC},
      {"TX:0801", 0xC19B},   {"PHSR:01", 0xE03E},  {"COMM:50000", 0x0048}, {"COMM:00000", 0x0084},
      {"GETINFO:Features.Firmware.Version", 0x0492}};
  for (const auto& [text, crc] : vectors) EXPECT_EQ(Crc16(std::string_view(text)), crc) << text;
  EXPECT_EQ(Crc16Hex("BX:0801"), "00EC");
}

TEST(NdiCrc, BxExampleHeaderAndBodyAndResidue) {
  EXPECT_EQ(Crc16(std::span(kBxExample).subspan(0, 4)), 0x433F);
  EXPECT_EQ(Crc16(std::span(kBxExample).subspan(6, 57)), 0x8525);
  // With init 0 and no final xor, the CRC over data and its little-endian CRC is zero (§2 residue).
  EXPECT_EQ(Crc16(std::span(kBxExample).subspan(6)), 0);
}

TEST(NdiCommands, FramingAddsCrcOnlyAfterColon) {
  EXPECT_EQ(FrameCommand(InitCommand()), "INIT:E3A5\r");
  EXPECT_EQ(FrameCommand(BxCommand(0x0801)), "BX:080100EC\r");
  EXPECT_EQ(FrameCommand(PhsrCommand(HandleQuery::kToBeFreed)), "PHSR:01E03E\r");
  EXPECT_EQ(FrameCommand(CommCommand(BaudRateFromBaud(115200))), "COMM:500000048\r");
  EXPECT_EQ(FrameCommand(CommCommand(BaudRateFromBaud(9600))), "COMM:000000084\r");
  EXPECT_EQ(FrameCommand(ApiRevCommand()), "APIREV \r");
  EXPECT_EQ(PenaCommand(0x0A, ToolMode::kDynamic), "PENA:0AD");
  EXPECT_EQ(PhrqPassiveCommand(), "PHRQ:*********1****");
  EXPECT_THROW(BaudRateFromBaud(12345), InputError);
}

TEST(NdiCommands, PvwrChunkIsZeroPadded128HexDigits) {
  const std::vector<uint8_t> chunk = {0x4E, 0x44, 0x49};
  const std::string command = PvwrCommand(0x0A, 0x40, chunk);
  EXPECT_EQ(command.substr(0, 15), "PVWR:0A00404E44");
  EXPECT_EQ(command.size(), 5u + 2 + 4 + 128);
  EXPECT_EQ(command.substr(command.size() - 4), "0000");
}

TEST(NdiReply, AsciiOkayErrorWarningReset) {
  auto okay = ParseAsciiReply("OKAYA896\r");
  ASSERT_TRUE(okay.ok());
  EXPECT_EQ(okay.value->kind, ReplyKind::kText);
  EXPECT_EQ(okay.value->text, "OKAY");

  auto error = ParseAsciiReply(FrameErrorReply(0x0D));
  ASSERT_TRUE(error.ok());
  EXPECT_EQ(error.value->kind, ReplyKind::kError);
  EXPECT_EQ(error.value->code, 0x0D);
  EXPECT_EQ(DescribeErrorReply(*error.value), "ERROR0D (No tool plugged in the selected port)");

  auto warning = ParseAsciiReply(FrameReply("WARNING02"));
  ASSERT_TRUE(warning.ok());
  EXPECT_EQ(warning.value->kind, ReplyKind::kWarning);
  EXPECT_EQ(warning.value->code, 2);

  auto reset = ParseAsciiReply("RESETBE6F\r");
  ASSERT_TRUE(reset.ok());
  EXPECT_EQ(reset.value->kind, ReplyKind::kReset);
  EXPECT_EQ(ErrorCodeMessage(0x04), "Invalid CRC calculated for command");
  EXPECT_EQ(ErrorCodeMessage(0x77), "unknown error code");
}

TEST(NdiReply, AsciiRejectsBadCrcShortAndNonHex) {
  auto bad = ParseAsciiReply("OKAYA897\r");
  ASSERT_FALSE(bad.ok());
  EXPECT_TRUE(IsCrcError(bad.error));
  EXPECT_EQ(bad.error.offset, 4u);
  EXPECT_FALSE(ParseAsciiReply("AB\r").ok());
  auto non_hex = ParseAsciiReply("OKAYA8Z6");
  ASSERT_FALSE(non_hex.ok());
  EXPECT_EQ(non_hex.error.offset, 6u);
  EXPECT_FALSE(IsCrcError(non_hex.error));
  EXPECT_FALSE(ParseAsciiReply(FrameReply("ERRORZZ")).ok());
}

TEST(NdiReply, PhsrAndHandle) {
  auto phsr = ParsePhsr("020A0310B001");
  ASSERT_TRUE(phsr.ok());
  ASSERT_EQ(phsr.value->size(), 2u);
  EXPECT_EQ((*phsr.value)[0].handle, 0x0A);
  EXPECT_EQ((*phsr.value)[0].status, 0x031);
  EXPECT_EQ((*phsr.value)[1].handle, 0x0B);
  auto truncated = ParsePhsr("020A0310B0");
  ASSERT_FALSE(truncated.ok());
  EXPECT_EQ(truncated.error.offset, 9u);  // the second handle's status is cut short
  EXPECT_FALSE(ParsePhsr("010A031X").ok());
  EXPECT_EQ(*ParseHandleReply("0A").value, 0x0A);
  EXPECT_FALSE(ParseHandleReply("0A1").ok());
}

TEST(NdiReply, BxWorkedExample) {
  auto parsed = ParseBx(kBxExample, 0x0001);
  ASSERT_TRUE(parsed.ok()) << parsed.error.ToString();
  const TrackingReply& reply = *parsed.value;
  ASSERT_EQ(reply.handles.size(), 3u);
  const HandleReport& valid = reply.handles[0];
  EXPECT_EQ(valid.handle, 0x0A);
  EXPECT_EQ(valid.status, HandleStatus::kValid);
  EXPECT_TRUE(valid.has_transform);
  EXPECT_DOUBLE_EQ(valid.q_wxyz[0], 1.0);
  EXPECT_DOUBLE_EQ(valid.t_mm[0], 10.5);
  EXPECT_DOUBLE_EQ(valid.t_mm[1], -20.25);
  EXPECT_DOUBLE_EQ(valid.t_mm[2], -1500.0);
  EXPECT_NEAR(valid.rms_error_mm, 0.12, 1e-6);
  EXPECT_EQ(valid.port_status, 0x31u);
  EXPECT_EQ(valid.frame_number, 123456u);
  const HandleReport& missing = reply.handles[1];
  EXPECT_EQ(missing.status, HandleStatus::kMissing);
  EXPECT_FALSE(missing.has_transform);
  EXPECT_TRUE(missing.has_port_status);
  EXPECT_EQ(missing.frame_number, 123456u);
  const HandleReport& disabled = reply.handles[2];
  EXPECT_EQ(disabled.handle, 0x0C);
  EXPECT_EQ(disabled.status, HandleStatus::kDisabled);
  EXPECT_FALSE(disabled.has_port_status);
  EXPECT_EQ(reply.system_status, 0);
}

TEST(NdiReply, EncodeBxReproducesWorkedExampleBytes) {
  const TrackingReply reply = *ParseBx(kBxExample, 0x0001).value;
  EXPECT_EQ(EncodeBx(reply), kBxExample);
}

TEST(NdiReply, BxStatusBitsAndSystemStatus) {
  TrackingReply reply;
  HandleReport oov;
  oov.handle = 1;
  oov.status = HandleStatus::kValid;
  oov.has_transform = true;
  oov.t_mm = {1, 2, 3};
  oov.port_status = 0x31 | port_status::kOutOfVolume;
  oov.frame_number = 7;
  HandleReport partial = oov;
  partial.handle = 2;
  partial.port_status = 0x31 | port_status::kPartiallyInVolume;
  reply.handles = {oov, partial};
  reply.system_status = system_status::kTooMuchInfrared | system_status::kPortOccupied;
  auto parsed = ParseBx(EncodeBx(reply), 0x0801);
  ASSERT_TRUE(parsed.ok());
  EXPECT_EQ(parsed.value->handles[0].port_status & port_status::kOutOfVolume, port_status::kOutOfVolume);
  EXPECT_EQ(parsed.value->handles[1].port_status & port_status::kPartiallyInVolume, port_status::kPartiallyInVolume);
  EXPECT_EQ(parsed.value->system_status, 0x42);
  EXPECT_EQ(DescribeSystemStatus(parsed.value->system_status), "too much external IR, port occupied");
}

// Option 0x0008 (§6): after port status and frame number, the tool's marker count, a bitmask of
// ceil(n/8) bytes and n xyz f32, for VALID and MISSING handles; nothing for DISABLED ones.
TEST(NdiReply, BxToolMarkersRoundTripAndCountInTheLength) {
  TrackingReply reply;
  HandleReport seen;
  seen.handle = 1;
  seen.status = HandleStatus::kValid;
  seen.has_transform = true;
  seen.markers_mm = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {-1.5, 2.5, -1500}};
  HandleReport missing;
  missing.handle = 2;
  missing.status = HandleStatus::kMissing;
  missing.markers_mm = {{10, 20, 30}};  // a tracker that sees too few markers to fit the tool
  HandleReport disabled;
  disabled.handle = 3;
  disabled.status = HandleStatus::kDisabled;
  reply.handles = {seen, missing, disabled};
  const std::vector<uint8_t> bytes = EncodeBx(reply, 0x0809);
  // Header 6 + count 1 + VALID (2 + 32 + 8 + 1 + 1 + 48) + MISSING (2 + 8 + 1 + 1 + 12) + DISABLED 2 + status 2 + CRC 2.
  EXPECT_EQ(bytes.size(), 6u + 1 + 92 + 24 + 2 + 2 + 2);
  auto parsed = ParseBx(bytes, 0x0809);
  ASSERT_TRUE(parsed.ok()) << parsed.error.message;
  ASSERT_EQ(parsed.value->handles.size(), 3u);
  EXPECT_EQ(parsed.value->handles[0].markers_mm.size(), 4u);
  EXPECT_EQ(parsed.value->handles[0].markers_mm[3][2], -1500.0);
  EXPECT_EQ(parsed.value->handles[1].markers_mm.size(), 1u);
  EXPECT_EQ(parsed.value->handles[1].markers_mm[0][1], 20.0);
  EXPECT_TRUE(parsed.value->handles[2].markers_mm.empty());
  EXPECT_FALSE(ParseBx(bytes, 0x0801).ok()) << "read without 0x0008 the marker bytes are left over";
}

TEST(NdiReply, BxEveryTruncationAndByteFlipIsAnErrorWithOffset) {
  for (size_t size = 0; size < kBxExample.size(); ++size) {
    auto parsed = ParseBx(std::span(kBxExample).subspan(0, size), 0x0001);
    ASSERT_FALSE(parsed.ok()) << size;
    EXPECT_LE(parsed.error.offset, kBxExample.size());
  }
  for (size_t at = 0; at < kBxExample.size(); ++at) {
    std::vector<uint8_t> flipped = kBxExample;
    flipped[at] ^= 0x10;
    EXPECT_FALSE(ParseBx(flipped, 0x0001).ok()) << "flip at " << at;  // every byte is covered by a CRC
  }
  std::vector<uint8_t> bad_body = kBxExample;
  bad_body[20] ^= 1;
  auto parsed = ParseBx(bad_body, 0x0001);
  EXPECT_TRUE(IsCrcError(parsed.error));
  EXPECT_EQ(parsed.error.offset, 63u);
}

TEST(NdiReply, BxBadStatusAndTrailingBytesNamed) {
  TrackingReply reply;
  HandleReport h;
  h.handle = 1;
  h.status = HandleStatus::kMissing;
  h.frame_number = 5;
  reply.handles = {h};
  std::vector<uint8_t> frame = EncodeBx(reply);
  // Rewrite the status byte to 0x03 and fix the body CRC: a well-framed but invalid reply.
  frame[8] = 0x03;
  const uint16_t crc = Crc16(std::span(frame).subspan(6, frame.size() - 8));
  frame[frame.size() - 2] = static_cast<uint8_t>(crc & 0xFF);
  frame[frame.size() - 1] = static_cast<uint8_t>(crc >> 8);
  auto parsed = ParseBx(frame, 0x0001);
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.error.offset, 7u);
  EXPECT_NE(parsed.error.message.find("none of VALID"), std::string::npos);
  EXPECT_FALSE(ParseBx(kBxExample, 0x0004).ok());  // single stray: refused, not guessed
}

TEST(NdiReply, BxWithMarkersAndPassiveStrays) {
  // Build option 0x1009 by hand: one VALID handle with 2 markers, then 1 passive stray.
  std::vector<uint8_t> body = {0x01, 0x05, 0x01};
  auto put_f32 = [&](float v) {
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    for (int i = 0; i < 4; ++i) body.push_back(static_cast<uint8_t>(bits >> (8 * i)));
  };
  auto put_u32 = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i) body.push_back(static_cast<uint8_t>(v >> (8 * i)));
  };
  for (float v : {1.f, 0.f, 0.f, 0.f, 1.f, 2.f, 3.f, 0.1f}) put_f32(v);
  put_u32(0x31);
  put_u32(99);
  body.push_back(2);     // markers
  body.push_back(0x02);  // second marker out of volume
  for (float v : {10.f, 11.f, 12.f, 20.f, 21.f, 22.f}) put_f32(v);
  body.push_back(1);
  body.push_back(0);
  for (float v : {-5.f, -6.f, -7.f}) put_f32(v);
  body.push_back(0);
  body.push_back(0);
  std::vector<uint8_t> frame = {0xC4, 0xA5, static_cast<uint8_t>(body.size()), 0};
  const uint16_t header_crc = Crc16(frame);
  frame.push_back(static_cast<uint8_t>(header_crc));
  frame.push_back(static_cast<uint8_t>(header_crc >> 8));
  frame.insert(frame.end(), body.begin(), body.end());
  const uint16_t body_crc = Crc16(body);
  frame.push_back(static_cast<uint8_t>(body_crc));
  frame.push_back(static_cast<uint8_t>(body_crc >> 8));
  auto parsed = ParseBx(frame, 0x1009);
  ASSERT_TRUE(parsed.ok()) << parsed.error.ToString();
  ASSERT_EQ(parsed.value->handles[0].markers_mm.size(), 2u);
  EXPECT_DOUBLE_EQ(parsed.value->handles[0].markers_mm[1][2], 22.0);
  ASSERT_EQ(parsed.value->passive_strays_mm.size(), 1u);
  EXPECT_DOUBLE_EQ(parsed.value->passive_strays_mm[0][0], -5.0);
  EXPECT_FALSE(ParseBx(frame, 0x0001).ok());  // same bytes read with the wrong options: trailing bytes
}

TEST(NdiReply, TxRoundTripWithMissingAndDisabled) {
  TrackingReply reply = *ParseBx(kBxExample, 0x0001).value;
  reply.handles[2].has_port_status = true;  // TX carries port status and frame for DISABLED too
  reply.handles[0].q_wxyz = {0.7071, 0.7071, 0, 0};
  const std::string text = EncodeTxText(reply);
  EXPECT_EQ(text.substr(0, 4), "030A");
  EXPECT_EQ(text.substr(4, 51), "+07071+07071+00000+00000+001050-002025-150000+01200");
  auto parsed = ParseTx(text, 0x0001);
  ASSERT_TRUE(parsed.ok()) << parsed.error.ToString();
  ASSERT_EQ(parsed.value->handles.size(), 3u);
  EXPECT_NEAR(parsed.value->handles[0].q_wxyz[1], 0.7071, 1e-9);
  EXPECT_NEAR(parsed.value->handles[0].t_mm[2], -1500.0, 1e-9);
  EXPECT_NEAR(parsed.value->handles[0].rms_error_mm, 0.12, 1e-9);
  EXPECT_EQ(parsed.value->handles[0].frame_number, 123456u);
  EXPECT_EQ(parsed.value->handles[1].status, HandleStatus::kMissing);
  EXPECT_EQ(parsed.value->handles[2].status, HandleStatus::kDisabled);
  // Through the ASCII layer: CRC appended and checked.
  auto ascii = ParseAsciiReply(FrameReply(text));
  ASSERT_TRUE(ascii.ok());
  EXPECT_EQ(ascii.value->text, text);
}

TEST(NdiReply, TxUnoccupiedSkippedAndErrorsHaveOffsets) {
  const std::string text = "020AUNOCCUPIED00000000\n0BMISSING000000310000000A\n0000";
  auto parsed = ParseTx(text, 0x0001);
  ASSERT_TRUE(parsed.ok()) << parsed.error.ToString();
  ASSERT_EQ(parsed.value->handles.size(), 1u);
  EXPECT_EQ(parsed.value->handles[0].handle, 0x0B);
  EXPECT_EQ(parsed.value->handles[0].frame_number, 10u);
  auto bad = ParseTx("010A+10000+00000", 0x0001);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error.offset, 16u);  // where the third quaternion field should start
  auto no_lf = ParseTx("010BMISSING000000310000000A0000", 0x0001);
  ASSERT_FALSE(no_lf.ok());
  EXPECT_EQ(no_lf.error.offset, 27u);
}

TEST(NdiReply, GarbageNeverCrashes) {
  uint64_t state = 42;
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<uint8_t> bytes(static_cast<size_t>(trial % 90));
    for (uint8_t& b : bytes) {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      b = static_cast<uint8_t>(state >> 56);
    }
    if (trial % 3 == 0 && bytes.size() >= 2) bytes[0] = 0xC4, bytes[1] = 0xA5;
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    EXPECT_FALSE(ParseBx(bytes, 0x0801).ok() && bytes.size() < 9);
    ParseTx(text, 0x0801);
    ParseAsciiReply(text);
    ParsePhsr(text);
  }
}

}  // namespace
}  // namespace mocap::ndi
