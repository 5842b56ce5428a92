#include "render/mesh_file_check.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

#include "core/check.h"
#include "core/text.h"
#include "render/mesh_file_check_internal.h"

namespace mocap {
namespace mesh_check {

namespace {

/// The whole token as a T (from_chars), a leading '+' allowed.
template <typename T>
std::optional<T> ParseWhole(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  T value = 0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (error != std::errc() || end != token.data() + token.size()) return std::nullopt;
  return value;
}

}  // namespace

/// A number in a text mesh file; a leading '+' is allowed, "nan" and "inf" parse (callers refuse them).
std::optional<double> ParseNumber(std::string_view token) { return ParseWhole<double>(token); }

std::optional<int64_t> ParseInteger(std::string_view token) { return ParseWhole<int64_t>(token); }

std::vector<std::string_view> SplitTokens(std::string_view line) {
  std::vector<std::string_view> tokens;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

}  // namespace mesh_check

namespace {

using namespace mesh_check;

// ---- OBJ ----

struct ObjCounts {
  int64_t vertices = 0, texcoords = 0, normals = 0;
};

void CheckObjVertex(const std::vector<std::string_view>& tokens, int64_t line, const std::string& path) {
  if (tokens.size() < 4)
    throw InputError(path, Str("line ", line, ": a vertex needs x y z, got ", tokens.size() - 1, " values"));
  for (size_t i = 1; i < tokens.size(); ++i) {
    const std::optional<double> value = ParseNumber(tokens[i]);
    if (!value || !std::isfinite(*value))
      throw InputError(path, Str("line ", line, ": vertex coordinate ", QuoteForMessage(tokens[i]),
                                 value ? " is not finite" : " is not a number"));
  }
}

/// What a face corner's index refers to, for messages.
struct ObjIndexKind {
  const char* one;
  const char* many;
};

/// One component of a face corner "v/vt/vn": 1-based, or negative counting back from the last one read.
void CheckObjIndex(std::string_view token, int64_t declared, ObjIndexKind kind, int64_t line, const std::string& path) {
  const std::optional<int64_t> index = ParseInteger(token);
  if (!index || *index == 0)
    throw InputError(path, Str("line ", line, ": ", kind.one, " index ", QuoteForMessage(token), " is not a non-zero integer"));
  if (*index > declared || *index < -declared)
    throw InputError(path, Str("line ", line, ": ", kind.one, " index ", *index, " is out of range: ", declared, " ", kind.many,
                               " declared so far"));
}

void CheckObjCorners(const std::vector<std::string_view>& tokens, const ObjCounts& counts, int64_t line,
                     const std::string& path) {
  for (size_t i = 1; i < tokens.size(); ++i) {
    std::string_view parts[3];
    std::string_view rest = tokens[i];
    for (int k = 0; k < 3; ++k) {
      const size_t slash = rest.find('/');
      parts[k] = rest.substr(0, slash);
      rest = slash == std::string_view::npos ? std::string_view() : rest.substr(slash + 1);
      if (slash == std::string_view::npos) break;
    }
    CheckObjIndex(parts[0], counts.vertices, {"vertex", "vertices"}, line, path);
    if (!parts[1].empty()) CheckObjIndex(parts[1], counts.texcoords, {"texture coordinate", "texture coordinates"}, line, path);
    if (!parts[2].empty()) CheckObjIndex(parts[2], counts.normals, {"normal", "normals"}, line, path);
  }
}

void CheckObj(std::string_view text, const std::string& path) {
  ObjCounts counts;
  int64_t line_number = 0;
  for (size_t start = 0; start < text.size();) {
    const size_t end = std::min(text.find('\n', start), text.size());
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++line_number;
    line = line.substr(0, line.find('#'));
    const std::vector<std::string_view> tokens = SplitTokens(line);
    if (tokens.empty()) continue;
    if (tokens[0] == "v") CheckObjVertex(tokens, line_number, path), ++counts.vertices;
    else if (tokens[0] == "vt") ++counts.texcoords;
    else if (tokens[0] == "vn") ++counts.normals;
    else if (tokens[0] == "f" || tokens[0] == "l" || tokens[0] == "p")
      CheckObjCorners(tokens, counts, line_number, path);
  }
}

// ---- STL ----

constexpr size_t kStlHeaderBytes = 84, kStlTriangleBytes = 50;

void CheckStl(std::string_view bytes, const std::string& path) {
  const uint32_t triangles = bytes.size() >= kStlHeaderBytes ? LoadScalar<uint32_t>(bytes.data() + 80, false) : 0;
  const uint64_t binary_bytes = kStlHeaderBytes + uint64_t{kStlTriangleBytes} * triangles;
  if (bytes.size() >= kStlHeaderBytes && binary_bytes == bytes.size()) {
    for (uint64_t t = 0; t < triangles; ++t) {
      const size_t vertices_at = kStlHeaderBytes + t * kStlTriangleBytes + 12;  // after the normal
      for (size_t k = 0; k < 9; ++k)
        if (!std::isfinite(LoadScalar<float>(bytes.data() + vertices_at + 4 * k, false)))
          throw InputError(path, Str("byte ", vertices_at + 4 * k, ": triangle ", t, " has a non-finite vertex coordinate"));
    }
    return;
  }
  const size_t text_start = std::min(bytes.find_first_not_of(" \t\r\n"), bytes.size());
  if (bytes.substr(text_start, 5) == "solid") return;  // a text STL: assimp reads it
  if (bytes.size() < kStlHeaderBytes)
    throw InputError(path, Str("byte ", bytes.size(), ": file ends inside the 84-byte header of a binary STL"));
  throw InputError(path, Str("byte 80: binary STL declares ", triangles, " triangles, which take 84 + 50 * ", triangles, " = ",
                             binary_bytes, " bytes, but the file has ", bytes.size(), " bytes (cut short or not an STL)"));
}

std::string LowercaseExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  return extension;
}

}  // namespace

void CheckMeshBytes(std::string_view bytes, const std::string& path) {
  const std::string extension = LowercaseExtension(path);
  if (extension == ".ply") CheckPly(bytes, path);
  else if (extension == ".obj") CheckObj(bytes, path);
  else if (extension == ".stl") CheckStl(bytes, path);
}

void CheckMeshFile(const std::string& path) {
  const std::string extension = LowercaseExtension(path);
  if (extension != ".ply" && extension != ".obj" && extension != ".stl") return;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open the mesh file (is it readable?)");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (in.bad()) throw InputError(path, "read error");
  CheckMeshBytes(bytes.str(), path);
}

}  // namespace mocap
