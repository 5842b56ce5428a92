#include "sim/ply_writer.h"

#include <bit>
#include <cstring>
#include <fstream>

#include "core/check.h"

namespace mocap::sim {
namespace {

static_assert(std::endian::native == std::endian::little, "the PLY writer assumes a little-endian host");

template <typename T>
void Append(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

}  // namespace

std::string EncodePlyBinary(const ColoredMesh& mesh, std::string_view comment) {
  MOCAP_CHECK(mesh.colors.size() == mesh.positions_m.size(), "one colour per vertex");
  MOCAP_CHECK(comment.find('\n') == std::string_view::npos, "PLY comment with a newline");
  std::string out = Str("ply\nformat binary_little_endian 1.0\ncomment ", comment, "\nelement vertex ",
                        mesh.positions_m.size(),
                        "\nproperty float x\nproperty float y\nproperty float z\n"
                        "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                        "element face ",
                        mesh.triangles.size(), "\nproperty list uchar int vertex_indices\nend_header\n");
  out.reserve(out.size() + mesh.positions_m.size() * 15 + mesh.triangles.size() * 13);
  for (size_t i = 0; i < mesh.positions_m.size(); ++i) {
    for (int k = 0; k < 3; ++k) Append(out, static_cast<float>(mesh.positions_m[i][k]));
    for (int k = 0; k < 3; ++k) Append(out, mesh.colors[i][k]);
  }
  for (const auto& tri : mesh.triangles) {
    Append(out, static_cast<uint8_t>(3));
    for (uint32_t index : tri) Append(out, static_cast<int32_t>(index));
  }
  return out;
}

void WritePlyBinary(const std::string& path, const ColoredMesh& mesh, std::string_view comment) {
  const std::string bytes = EncodePlyBinary(mesh, comment);
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) throw InputError(path, "cannot open for writing (does the folder exist and is it writable?)");
  file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!file) throw InputError(path, "write failed (disk full?)");
}

}  // namespace mocap::sim
