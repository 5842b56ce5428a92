#pragma once
// Checksummed JSON lines: the framing of every append-only stream of a session.
//
// A record is one line: the compact JSON object, a TAB, the CRC-32 (zlib/IEEE 802.3 polynomial) of the
// JSON bytes as 8 lowercase hex digits, and '\n'. Compact JSON never holds a raw TAB or newline, so the
// framing is unambiguous. A line that lacks its '\n', its TAB or a matching checksum is not a record.
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace mocap {

uint32_t Crc32(std::string_view bytes);

/// The framed line for `record`, newline included.
std::string EncodeRecordLine(const nlohmann::json& record);

struct RecordLine {
  int64_t line = 0;  ///< 1-based line number in the file
  nlohmann::json json;
};

struct RecordFileContents {
  std::vector<RecordLine> records;
  bool torn_tail = false;     ///< the last line was incomplete or bad, and was dropped
  int64_t corrupt_lines = 0;  ///< bad lines before the last one that were skipped
};

/// Reads a stream file. A bad last line (a torn append) is dropped and flagged. A bad line before the
/// last throws InputError("file:line", ...) unless `skip_corrupt`, in which case it is counted and
/// skipped. A missing file reads as empty (a stream that never got a record).
RecordFileContents ReadRecordFile(const std::filesystem::path& path, bool skip_corrupt);

}  // namespace mocap
