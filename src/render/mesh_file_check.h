#pragma once
// A consistency check of mesh files before assimp reads them. Assimp trusts the counts a file declares:
// a PLY cut inside its face list, or a face naming a vertex that does not exist, crashes it (SIGSEGV, or
// SIGABRT in its asserts). The check walks the file once and throws InputError naming the file and the
// first inconsistency's position: "byte N" in binary data, "line N" in text.
//
// Checked, by extension (case-insensitive):
//  - .ply (ascii, binary_little_endian, binary_big_endian): the header (types, counts, end_header); the
//    body element by element: the file holds every declared row, list counts are sane, face lists name
//    existing vertices (3..64 corners), vertex coordinates x, y, z are finite numbers.
//  - .obj: vertex coordinates are finite numbers; face, line and point indices (positive or relative)
//    name vertices, texture coordinates and normals declared before them.
//  - .stl: a binary STL is 84 + 50 * n bytes for its n triangles, with finite vertices; a text STL starts
//    with "solid" (assimp reads the rest).
//  - anything else: left to assimp.
#include <string>
#include <string_view>

namespace mocap {

/// Reads `path` and checks it (see above). Throws InputError(path, "...") on the first inconsistency.
void CheckMeshFile(const std::string& path);

/// The same check on bytes in memory; `path` names the file in messages and its extension picks the format.
void CheckMeshBytes(std::string_view bytes, const std::string& path);

}  // namespace mocap
