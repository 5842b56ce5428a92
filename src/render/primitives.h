#pragma once
// Simple generated meshes (metres, mesh frame at their centre): the doctor's test cube, markers and
// planes for projection and depth tests, and benchmark objects of a chosen triangle count. Closed meshes
// have outward, counter-clockwise faces.
#include "render/mesh.h"

namespace mocap {

/// Axis-aligned box with the given edge lengths, 12 triangles, centred at the origin.
Mesh MakeBoxMesh(const Eigen::Vector3d& size_m);
/// Flat disc in the mesh's z = 0 plane, centred at the origin, as a fan of `segments` triangles.
Mesh MakeDiscMesh(double radius_m, int segments = 48);
/// Rectangle in the z = 0 plane, centred at the origin, 2 triangles.
Mesh MakeRectangleMesh(double width_m, double height_m);
/// UV sphere with about `triangles` triangles (at least 8x4 segments), centred at the origin.
Mesh MakeSphereMesh(double radius_m, int triangles);

}  // namespace mocap
