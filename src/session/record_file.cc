#include "session/record_file.h"

#include <zlib.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/check.h"

namespace mocap {
namespace fs = std::filesystem;

uint32_t Crc32(std::string_view bytes) {
  uLong crc = crc32(0L, Z_NULL, 0);
  // zlib takes uInt lengths; records are far below 4 GiB, but feed in chunks to be exact.
  while (!bytes.empty()) {
    const size_t chunk = std::min<size_t>(bytes.size(), 1u << 30);
    crc = crc32(crc, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(chunk));
    bytes.remove_prefix(chunk);
  }
  return static_cast<uint32_t>(crc);
}

std::string EncodeRecordLine(const nlohmann::json& record) {
  std::string line = record.dump();
  char crc[16];
  std::snprintf(crc, sizeof(crc), "\t%08x\n", Crc32(line));
  line += crc;
  return line;
}

namespace {

/// Parses one line (without '\n'); empty result and `reason` set when it is not a valid record.
bool DecodeLine(std::string_view line, nlohmann::json* json, std::string* reason) {
  const size_t tab = line.rfind('\t');
  if (tab == std::string_view::npos || line.size() - tab != 9) {
    *reason = "no checksum (the line is incomplete or not a session record)";
    return false;
  }
  const std::string_view body = line.substr(0, tab);
  char expected[9];
  std::snprintf(expected, sizeof(expected), "%08x", Crc32(body));
  if (line.substr(tab + 1) != std::string_view(expected, 8)) {
    *reason = "checksum mismatch (the record is corrupt)";
    return false;
  }
  *json = nlohmann::json::parse(body, nullptr, /*allow_exceptions=*/false);
  if (json->is_discarded() || !json->is_object()) {
    *reason = "checksum matches but the record is not a JSON object";
    return false;
  }
  return true;
}

}  // namespace

RecordFileContents ReadRecordFile(const fs::path& path, bool skip_corrupt) {
  RecordFileContents contents;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (!fs::exists(path)) return contents;
    throw InputError(path.string(), "cannot open the stream file");
  }
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string data = buffer.str();
  size_t start = 0;
  for (int64_t line_number = 1; start < data.size(); ++line_number) {
    const size_t end = data.find('\n', start);
    const bool last = end == std::string::npos || end + 1 == data.size();
    const std::string_view line(data.data() + start, (end == std::string::npos ? data.size() : end) - start);
    RecordLine record{line_number, {}};
    std::string reason;
    const bool ok = end != std::string::npos && DecodeLine(line, &record.json, &reason);
    if (ok) {
      contents.records.push_back(std::move(record));
    } else if (last) {
      contents.torn_tail = true;
    } else if (skip_corrupt) {
      ++contents.corrupt_lines;
    } else {
      throw InputError(Str(path.string(), ":", line_number), reason);
    }
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return contents;
}

}  // namespace mocap
