#pragma once
// Whether skipping back faces can change what a camera sees of a mesh. It cannot for a solid bounded by
// closed, outward-wound shells seen from outside: a ray from the camera that hits a shell enters it
// first, through a face whose outward normal points back at the camera, so the nearest surface along
// every ray (the depth, and so every mask) is a front face. The renderer culls a mesh only when this
// holds and, per draw, only while the mesh's bounding box lies wholly beyond the near plane (then the
// camera is outside the solid and no ray starts inside it; renderer.cc).
//
// The check, on vertices welded by exact position (loaders split vertices at colour and UV seams):
// every edge is shared by exactly two triangles that traverse it in opposite directions (closed,
// edge-manifold, consistently oriented), and every connected shell has a positive signed volume
// (counter-clockwise seen from outside). Triangles with two welded corners equal cover no pixel and are
// ignored. Conservative: a solid with a cavity (an inward shell inside an outward one) is classified as
// not closed and stays unculled although culling would be exact; self-intersecting shells are not
// detected (a scan or CAD export practically never is one while also passing the checks above).
#include <cstdint>
#include <string>

#include "render/mesh.h"

namespace mocap {

/// Back-face culling of a mesh. kAuto culls exactly where it cannot change the image: meshes that
/// AnalyzeClosure (below) finds closed and outward-wound, and only in draws where the mesh's
/// bounding box lies wholly beyond the near plane (so the camera is outside the solid). kAlways culls
/// any mesh (the caller vouches that it is closed and outward; with holes its inside is missing, with
/// inward winding it disappears) under the same near-plane condition; kNever draws every face.
enum class BackFaceCulling { kNever, kAuto, kAlways };

/// "never", "auto", "always"; throws InputError for another name.
BackFaceCulling BackFaceCullingFromString(const std::string& name);
const char* ToString(BackFaceCulling culling);

struct MeshClosure {
  int64_t welded_vertices = 0;
  int64_t triangles = 0;           ///< non-degenerate triangles checked
  int64_t boundary_edges = 0;      ///< in one triangle only (a hole or an open border)
  int64_t misoriented_edges = 0;   ///< in two triangles traversing it the same way (inconsistent winding)
  int64_t nonmanifold_edges = 0;   ///< in more than two triangles
  int shells = 0;                  ///< connected components
  int inward_shells = 0;           ///< shells with signed volume <= 0 (inward winding, or flat)
  double volume_m3 = 0;            ///< signed volume of the whole mesh (outward counter-clockwise > 0)

  /// Back-face culling is exact for the mesh seen from outside (the header's conditions).
  bool culling_exact() const;
  /// "closed, 1 shell, 2.1e-04 m^3" or why culling is not exact ("12 boundary edges, ...").
  std::string Describe() const;
};

/// Analyses `mesh`'s topology and orientation (linear in its size apart from a sort of the edges).
MeshClosure AnalyzeClosure(const Mesh& mesh);

}  // namespace mocap
