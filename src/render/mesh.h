#pragma once
// Triangle meshes of the objects, read with assimp (PLY, OBJ, STL, glTF, and what assimp reads), in
// metres after the object's declared unit scale. Vertex colours and textures are kept for colour
// rendering (the simulator); labels need only the geometry.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace mocap {

/// An 8-bit RGB texture image, row-major, first row = top of the image file.
struct TextureRgb8 {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  ///< width * height * 3
  bool empty() const { return rgb.empty(); }
};

struct Mesh {
  std::string source;                        ///< file it was read from (for messages)
  std::vector<Eigen::Vector3f> positions_m;  ///< mesh frame, metres
  std::vector<uint32_t> indices;             ///< 3 per triangle, into positions_m
  std::vector<Eigen::Vector4f> colors;       ///< RGBA in [0, 1] per vertex; empty when the file has none
  std::vector<Eigen::Vector2f> uvs;          ///< per vertex, (0, 0) = bottom-left of the texture; or empty
  TextureRgb8 texture;                       ///< diffuse texture; empty when none

  size_t triangle_count() const { return indices.size() / 3; }
  Eigen::Vector3f min_m() const;  ///< axis-aligned bounds, mesh frame. Precondition: not empty.
  Eigen::Vector3f max_m() const;
  /// Length of the bounding-box diagonal, metres.
  double extent_m() const;
};

struct MeshLoadOptions {
  /// Plausible range of an object's bounding-box diagonal, metres: a mesh outside it almost certainly
  /// has the wrong declared unit (a mesh in mm declared as metres is 1000x too big). 0 disables a bound.
  double min_extent_m = 0.005;
  double max_extent_m = 5.0;
  void check() const;
};

/// Whether a mesh's size fits its declared unit, and if not, which unit would.
struct MeshUnitCheck {
  bool ok = true;
  double extent_m = 0;        ///< bounding-box diagonal with the declared unit
  double likely_scale_to_m = 0;  ///< a unit scale giving a plausible size (0 when none does)
  std::string likely_unit;    ///< "m", "cm", "mm", "in" or empty
  std::string message;        ///< empty when ok
};

/// Checks the extent of `mesh` (already scaled by `declared_scale_to_m`) against the plausible range.
MeshUnitCheck CheckMeshUnit(const Mesh& mesh, double declared_scale_to_m, const MeshLoadOptions& options = {});

/// Name of a unit scale ("m" for 1, "mm" for 0.001, ...), or the number when it is not a common unit.
std::string UnitName(double scale_to_m);

/// Reads a mesh file and scales it to metres (`unit_scale_to_m`: 0.001 for a mesh in mm). Throws
/// InputError naming the file when it is missing, unreadable, has no triangles, or (unless disabled in
/// options) its extent does not fit the declared unit, naming the extent and the likely unit.
Mesh LoadMesh(const std::string& path, double unit_scale_to_m, const MeshLoadOptions& options = {});

}  // namespace mocap
