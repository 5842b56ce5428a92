#pragma once
// Procedural triangle meshes with vertex colours, built from closed shells (surfaces of revolution with
// superelliptic cross-sections, boxes, swept tubes). Every shell is closed and oriented outwards, so the
// whole mesh has every edge shared by exactly two triangles in opposite directions and a positive
// volume; shells may interpenetrate (the renderer and the labeller need a closed surface, not a
// boolean union). Units: metres.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "core/rigid3.h"
#include "sim/color_image.h"

namespace mocap::sim {

struct ColoredMesh {
  std::vector<Eigen::Vector3d> positions_m;
  std::vector<Rgb8> colors;                     ///< one per vertex
  std::vector<std::array<uint32_t, 3>> triangles;  ///< counter-clockwise seen from outside

  size_t vertex_count() const { return positions_m.size(); }
  size_t triangle_count() const { return triangles.size(); }
};

/// One ring of a generalised surface of revolution: a superellipse |x/rx|^n + |y/ry|^n = 1 centred at
/// (cx, cy) at height z. n = 2 is an ellipse; larger n tends to a rounded rectangle.
struct LatheRing {
  double z_m = 0;
  double rx_m = 0, ry_m = 0;
  double exponent = 2.0;
  double cx_m = 0, cy_m = 0;
  Rgb8 color{200, 200, 200};
};

class MeshBuilder {
 public:
  /// A closed shell through `rings`, bottom to top. A ring with rx = ry = 0 at either end becomes a
  /// pole (a triangle fan), so a profile from pole to pole is a sphere-like shell; a profile without
  /// poles is closed into a tube-like (torus) shell by joining the last ring to the first.
  /// Precondition: at least 2 rings; `segments` >= 3. `T_mesh_shell` places the shell.
  void AddLathe(const std::vector<LatheRing>& rings, int segments, const Rigid3d& T_mesh_shell = {});
  /// A closed cylinder of radius r from z0 to z1 along the shell's z axis.
  void AddCylinder(double radius_m, double z0_m, double z1_m, int segments, Rgb8 color,
                   const Rigid3d& T_mesh_shell = {});
  /// An axis-aligned box (in the shell frame) centred at the origin with the given half extents.
  void AddBox(const Eigen::Vector3d& half_extents_m, Rgb8 color, const Rigid3d& T_mesh_shell = {});
  /// A tube of circular cross-section (radius r) swept along a closed planar polyline `path_m`
  /// (at least 3 points, in the shell frame); a handle or a ring.
  void AddClosedTube(const std::vector<Eigen::Vector3d>& path_m, double radius_m, int segments, Rgb8 color,
                     const Rigid3d& T_mesh_shell = {});

  const ColoredMesh& mesh() const { return mesh_; }
  ColoredMesh Take() { return std::move(mesh_); }

 private:
  uint32_t AddVertex(const Eigen::Vector3d& p, Rgb8 color);
  void AddQuad(uint32_t a, uint32_t b, uint32_t c, uint32_t d);
  /// Flips the triangles from `first_triangle` on when their signed volume is negative, so every shell
  /// faces outwards whatever the winding its generator produced.
  void OrientShell(size_t first_triangle);

  ColoredMesh mesh_;
};

}  // namespace mocap::sim
