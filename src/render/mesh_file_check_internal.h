#pragma once
// Pieces shared by the mesh file checks: mesh_file_check.cc (dispatch, OBJ, STL) and
// mesh_file_check_ply.cc (PLY). Not part of the render module's interface.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mocap::mesh_check {

/// A number in a text mesh file; a leading '+' is allowed; "nan" and "inf" parse (callers refuse them).
std::optional<double> ParseNumber(std::string_view token);
/// A decimal integer, with an optional leading sign.
std::optional<int64_t> ParseInteger(std::string_view token);
/// The whitespace-separated tokens of one line ('\r' counts as whitespace).
std::vector<std::string_view> SplitTokens(std::string_view line);

/// The T stored at `bytes` (any alignment) in big- or little-endian byte order.
template <typename T>
T LoadScalar(const char* bytes, bool big_endian) {
  char raw[sizeof(T)];
  std::memcpy(raw, bytes, sizeof(T));
  if (big_endian != (std::endian::native == std::endian::big)) std::reverse(raw, raw + sizeof(T));
  T value;
  std::memcpy(&value, raw, sizeof(T));
  return value;
}

/// The PLY check (mesh_file_check.h): throws InputError(path, ...) on the first inconsistency.
void CheckPly(std::string_view bytes, const std::string& path);

}  // namespace mocap::mesh_check
