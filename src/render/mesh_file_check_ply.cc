// The PLY part of the mesh file check (mesh_file_check.h): the header, then the body walked element by
// element, row by row, in the declared format.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "core/check.h"
#include "core/text.h"
#include "render/mesh_file_check_internal.h"

namespace mocap::mesh_check {
namespace {

/// Corners a face may have: fewer is no polygon, more is no scanned mesh this tool expects.
constexpr int64_t kMinFaceCorners = 3, kMaxFaceCorners = 64;
constexpr int64_t kMaxRows = 2147483647;

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

std::optional<PlyType> PlyTypeNamed(std::string_view name) {
  static constexpr std::pair<std::string_view, PlyType> kNames[] = {
      {"char", PlyType::kInt8},     {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
      {"uint8", PlyType::kUint8},   {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16}, {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},   {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32}, {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  for (const auto& [n, type] : kNames)
    if (n == name) return type;
  return std::nullopt;
}

size_t SizeBytes(PlyType type) {
  switch (type) {
    case PlyType::kInt8: case PlyType::kUint8: return 1;
    case PlyType::kInt16: case PlyType::kUint16: return 2;
    case PlyType::kInt32: case PlyType::kUint32: case PlyType::kFloat32: return 4;
    case PlyType::kFloat64: return 8;
  }
  return 0;
}

bool IsInteger(PlyType type) { return type != PlyType::kFloat32 && type != PlyType::kFloat64; }

/// What the check looks at in a property: vertex coordinates must be finite, face corners must exist.
enum class Role { kOther, kCoordinate, kVertexIndices };

/// A name from the file as messages show it: as it is when it is a plain word, else quoted and escaped.
std::string Label(std::string_view name) {
  const bool plain = !name.empty() && std::all_of(name.begin(), name.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '_' || c == '-';
  });
  return plain ? std::string(name) : QuoteForMessage(name);
}

struct PlyProperty {
  std::string name;
  std::string label;                       ///< name for messages (Label)
  PlyType type = PlyType::kUint8;          ///< a scalar's type; a list's item type
  std::optional<PlyType> list_count_type;  ///< set for a list
  Role role = Role::kOther;
};

struct PlyElement {
  std::string name;
  std::string label;  ///< name for messages (Label)
  int64_t count = 0;
  int64_t header_line = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  bool ascii = true, big_endian = false;
  std::vector<PlyElement> elements;
  int64_t vertex_count = 0;
  size_t body_offset_bytes = 0;  ///< first byte after the end_header line
  int64_t body_first_line = 0;
};

/// Where a problem is: "byte N" in binary bodies, "line N" in text.
struct Position {
  const char* unit;
  int64_t value;
};
std::ostream& operator<<(std::ostream& out, const Position& p) { return out << p.unit << ' ' << p.value; }

void ParseElementLine(const std::vector<std::string_view>& tokens, int64_t line, PlyHeader& header,
                      const std::string& path) {
  const std::optional<int64_t> count = tokens.size() == 3 ? ParseInteger(tokens[2]) : std::nullopt;
  if (!count) throw InputError(path, Str("line ", line, ": expected 'element <name> <count>'"));
  // Assimp counts rows in 32 bits; a count beyond that is a corrupt header (a smaller one too large for the
  // file is found by the body check, which names where the file ends).
  if (*count < 0 || *count > kMaxRows)
    throw InputError(path, Str("line ", line, ": element ", QuoteForMessage(tokens[1]), " declares ", *count,
                               " rows, outside 0..", kMaxRows, " (corrupt header?)"));
  header.elements.push_back({std::string(tokens[1]), Label(tokens[1]), *count, line, {}});
}

void ParsePropertyLine(const std::vector<std::string_view>& tokens, int64_t line, PlyHeader& header, const std::string& path) {
  if (header.elements.empty()) throw InputError(path, Str("line ", line, ": property before any element"));
  const bool list = tokens.size() >= 2 && tokens[1] == "list";
  if (tokens.size() != (list ? 5u : 3u))
    throw InputError(path, Str("line ", line, ": expected 'property <type> <name>' or ",
                               "'property list <count type> <item type> <name>'"));
  PlyProperty property;
  property.name = std::string(tokens.back());
  property.label = Label(tokens.back());
  const std::optional<PlyType> type = PlyTypeNamed(tokens[list ? 3 : 1]);
  if (!type) throw InputError(path, Str("line ", line, ": unknown PLY type ", QuoteForMessage(tokens[list ? 3 : 1])));
  property.type = *type;
  if (list) {
    property.list_count_type = PlyTypeNamed(tokens[2]);
    if (!property.list_count_type || !IsInteger(*property.list_count_type))
      throw InputError(path, Str("line ", line, ": a list count type must be an integer type, not ",
                                 QuoteForMessage(tokens[2])));
  }
  header.elements.back().properties.push_back(property);
}

/// Marks the properties the body check looks at and refuses elements it cannot walk.
void FinishHeader(PlyHeader& header, const std::string& path) {
  for (PlyElement& element : header.elements) {
    if (element.count > 0 && element.properties.empty())
      throw InputError(path, Str("line ", element.header_line, ": element ", element.label, " has rows but no properties"));
    if (element.name == "vertex") header.vertex_count = element.count;
    for (PlyProperty& p : element.properties) {
      if (element.name == "vertex" && !p.list_count_type && (p.name == "x" || p.name == "y" || p.name == "z"))
        p.role = Role::kCoordinate;
      if (element.name == "face" && p.list_count_type && (p.name == "vertex_indices" || p.name == "vertex_index")) {
        if (!IsInteger(p.type))
          throw InputError(path, Str("line ", element.header_line, ": face property ", p.label, " must be a list of integers"));
        p.role = Role::kVertexIndices;
      }
    }
  }
}

void ParseHeaderLine(const std::vector<std::string_view>& tokens, int64_t line, PlyHeader& header, const std::string& path) {
  if (tokens[0] == "format") {
    if (tokens.size() != 3 || (tokens[1] != "ascii" && tokens[1] != "binary_little_endian" && tokens[1] != "binary_big_endian"))
      throw InputError(path, Str("line ", line, ": expected 'format ascii|binary_little_endian|binary_big_endian 1.0'"));
    header.ascii = tokens[1] == "ascii";
    header.big_endian = tokens[1] == "binary_big_endian";
  } else if (tokens[0] == "element") {
    ParseElementLine(tokens, line, header, path);
  } else if (tokens[0] == "property") {
    ParsePropertyLine(tokens, line, header, path);
  } else if (tokens[0] != "comment" && tokens[0] != "obj_info") {
    throw InputError(path, Str("line ", line, ": unknown PLY header keyword ", QuoteForMessage(tokens[0])));
  }
}

PlyHeader ParsePlyHeader(std::string_view bytes, const std::string& path) {
  PlyHeader header;
  bool have_format = false;
  size_t offset = 0;
  for (int64_t line = 1;; ++line) {
    const size_t end = bytes.find('\n', offset);
    if (end == std::string_view::npos)
      throw InputError(path, Str("line ", line, ": file ends inside the PLY header (no end_header line)"));
    const std::vector<std::string_view> tokens = SplitTokens(bytes.substr(offset, end - offset));
    offset = end + 1;
    if (line == 1) {
      if (tokens.size() != 1 || tokens[0] != "ply")
        throw InputError(path, "line 1: not a PLY file (the first line is not 'ply')");
      continue;
    }
    if (tokens.empty()) continue;
    if (tokens[0] == "end_header") {
      if (!have_format) throw InputError(path, Str("line ", line, ": the PLY header has no format line"));
      FinishHeader(header, path);
      header.body_offset_bytes = offset;
      header.body_first_line = line + 1;
      return header;
    }
    have_format = have_format || tokens[0] == "format";
    ParseHeaderLine(tokens, line, header, path);
  }
}

void CheckListCount(int64_t count, const PlyProperty& p, const PlyElement& e, int64_t row, Position at,
                    const std::string& path) {
  if (count < 0) throw InputError(path, Str(at, ": ", e.label, " ", row, " has a list ", p.label, " of ", count, " items"));
  if (p.role == Role::kVertexIndices && (count < kMinFaceCorners || count > kMaxFaceCorners))
    throw InputError(path, Str(at, ": ", e.label, " ", row, " has ", count, " corners; a face has ", kMinFaceCorners, "..",
                               kMaxFaceCorners));
}

void CheckVertexIndex(double index, int64_t vertex_count, const PlyElement& e, int64_t row, Position at,
                      const std::string& path) {
  if (!(index >= 0 && index < static_cast<double>(vertex_count) && index == std::floor(index)))
    throw InputError(path, Str(at, ": ", e.label, " ", row, " refers to vertex ", index, ", but the file declares ", vertex_count,
                               " vertices"));
}

void CheckCoordinate(double value, const PlyProperty& p, const PlyElement& e, int64_t row, Position at,
                     const std::string& path) {
  if (!std::isfinite(value))
    throw InputError(path, Str(at, ": ", e.label, " ", row, " has a non-finite coordinate ", p.label, " = ", value));
}

/// The body of a binary PLY, walked value by value.
class BinaryBody {
 public:
  BinaryBody(std::string_view bytes, const PlyHeader& header, const std::string& path)
      : bytes_(bytes), header_(header), path_(path), offset_(header.body_offset_bytes) {}

  void Check() {
    for (const PlyElement& element : header_.elements)
      for (int64_t row = 0; row < element.count; ++row)
        for (const PlyProperty& p : element.properties) CheckValue(p, element, row);
  }

 private:
  void CheckValue(const PlyProperty& p, const PlyElement& e, int64_t row) {
    if (!p.list_count_type) {
      const double value = Load(p.type, e, row);
      if (p.role == Role::kCoordinate) CheckCoordinate(value, p, e, row, Here(SizeBytes(p.type)), path_);
      return;
    }
    const auto count = static_cast<int64_t>(Load(*p.list_count_type, e, row));
    CheckListCount(count, p, e, row, Here(SizeBytes(*p.list_count_type)), path_);
    if (p.role != Role::kVertexIndices) {
      Need(static_cast<uint64_t>(count) * SizeBytes(p.type), e, row);
      offset_ += static_cast<size_t>(count) * SizeBytes(p.type);
      return;
    }
    for (int64_t k = 0; k < count; ++k) {
      const double index = Load(p.type, e, row);
      CheckVertexIndex(index, header_.vertex_count, e, row, Here(SizeBytes(p.type)), path_);
    }
  }

  /// The position of the value just read, `size` bytes long.
  Position Here(size_t size) const { return {"byte", static_cast<int64_t>(offset_ - size)}; }

  void Need(uint64_t size, const PlyElement& e, int64_t row) const {
    if (size > bytes_.size() - offset_)
      throw InputError(path_, Str("byte ", bytes_.size(), ": file ends inside the ", e.label, " list (", e.label, " ", row,
                                  " of ", e.count, " declared)"));
  }

  double Load(PlyType type, const PlyElement& e, int64_t row) {
    Need(SizeBytes(type), e, row);
    const char* at = bytes_.data() + offset_;
    offset_ += SizeBytes(type);
    const bool big = header_.big_endian;
    switch (type) {
      case PlyType::kInt8: return LoadScalar<int8_t>(at, big);
      case PlyType::kUint8: return LoadScalar<uint8_t>(at, big);
      case PlyType::kInt16: return LoadScalar<int16_t>(at, big);
      case PlyType::kUint16: return LoadScalar<uint16_t>(at, big);
      case PlyType::kInt32: return LoadScalar<int32_t>(at, big);
      case PlyType::kUint32: return LoadScalar<uint32_t>(at, big);
      case PlyType::kFloat32: return LoadScalar<float>(at, big);
      case PlyType::kFloat64: return LoadScalar<double>(at, big);
    }
    return 0;
  }

  std::string_view bytes_;
  const PlyHeader& header_;
  const std::string& path_;
  size_t offset_;
};

/// The body of an ascii PLY: one row per line, one token per scalar, a count and its items per list.
class AsciiBody {
 public:
  AsciiBody(std::string_view bytes, const PlyHeader& header, const std::string& path)
      : bytes_(bytes), header_(header), path_(path), offset_(header.body_offset_bytes), line_(header.body_first_line - 1) {}

  void Check() {
    for (const PlyElement& element : header_.elements)
      for (int64_t row = 0; row < element.count; ++row) CheckRow(element, row);
  }

 private:
  void CheckRow(const PlyElement& e, int64_t row) {
    const std::vector<std::string_view> tokens = NextRow(e, row);
    const Position at{"line", line_};
    size_t next = 0;
    auto take = [&]() -> std::string_view {
      if (next < tokens.size()) return tokens[next++];
      if (offset_ > bytes_.size()) ThrowFileEnds(e, row);  // the last line, cut short
      throw InputError(path_, Str(at, ": ", e.label, " ", row, " has ", tokens.size(), " values, too few for its properties"));
    };
    for (const PlyProperty& p : e.properties) {
      if (!p.list_count_type) {
        const double value = Number(take(), p, e, row);
        if (p.role == Role::kCoordinate) CheckCoordinate(value, p, e, row, at, path_);
        continue;
      }
      const std::string_view count_token = take();
      const std::optional<int64_t> count = ParseInteger(count_token);
      if (!count)
        throw InputError(path_, Str(at, ": list count ", QuoteForMessage(count_token), " of ", e.label, " ", row,
                                    " is not an integer"));
      CheckListCount(*count, p, e, row, at, path_);
      for (int64_t k = 0; k < *count; ++k) {
        const double item = Number(take(), p, e, row);
        if (p.role == Role::kVertexIndices) CheckVertexIndex(item, header_.vertex_count, e, row, at, path_);
      }
    }
    if (next != tokens.size())
      throw InputError(path_, Str(at, ": ", e.label, " ", row, " has ", tokens.size(), " values, its properties take ", next));
  }

  /// The tokens of the next non-blank line.
  std::vector<std::string_view> NextRow(const PlyElement& e, int64_t row) {
    while (offset_ < bytes_.size()) {
      const size_t end = std::min(bytes_.find('\n', offset_), bytes_.size());
      std::vector<std::string_view> tokens = SplitTokens(bytes_.substr(offset_, end - offset_));
      offset_ = end + 1;
      ++line_;
      if (!tokens.empty()) return tokens;
    }
    ++line_;
    ThrowFileEnds(e, row);
  }

  [[noreturn]] void ThrowFileEnds(const PlyElement& e, int64_t row) const {
    throw InputError(path_, Str("line ", line_, ": file ends inside the ", e.label, " list (", e.label, " ", row, " of ", e.count,
                                " declared)"));
  }

  double Number(std::string_view token, const PlyProperty& p, const PlyElement& e, int64_t row) const {
    const std::optional<double> value = ParseNumber(token);
    if (!value)
      throw InputError(path_, Str("line ", line_, ": ", QuoteForMessage(token), " is not a number (", p.label, " of ", e.label,
                                  " ", row, ")"));
    return *value;
  }

  std::string_view bytes_;
  const PlyHeader& header_;
  const std::string& path_;
  size_t offset_;
  int64_t line_;  ///< number of the line last read
  // offset_ is past bytes_.size() after reading a last line that has no '\n'.
};

}  // namespace

void CheckPly(std::string_view bytes, const std::string& path) {
  const PlyHeader header = ParsePlyHeader(bytes, path);
  if (header.ascii) AsciiBody(bytes, header, path).Check();
  else BinaryBody(bytes, header, path).Check();
}

}  // namespace mocap::mesh_check
