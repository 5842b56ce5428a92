#pragma once
// Binary little-endian PLY with per-vertex colours: float x y z (metres), uchar red green blue, and
// faces as "list uchar int". The bytes depend only on the mesh (no dates), so regenerating a mesh
// reproduces its file exactly.
#include <string>
#include <string_view>

#include "sim/mesh_builder.h"

namespace mocap::sim {

/// The whole file as bytes; `comment` lines go into the header (no newlines inside).
std::string EncodePlyBinary(const ColoredMesh& mesh, std::string_view comment);
/// Writes EncodePlyBinary() to `path`; throws InputError when the file cannot be written.
void WritePlyBinary(const std::string& path, const ColoredMesh& mesh, std::string_view comment);

}  // namespace mocap::sim
