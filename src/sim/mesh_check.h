#pragma once
// Topology and size checks of a generated mesh: closed (every edge in exactly two triangles), consistently
// oriented (each directed edge once, its reverse once), positive enclosed volume, bounding box.
#include <Eigen/Core>
#include <cstddef>

#include "sim/mesh_builder.h"

namespace mocap::sim {

struct MeshTopologyReport {
  size_t edges = 0;               ///< undirected edges
  size_t boundary_edges = 0;      ///< in one triangle only
  size_t non_manifold_edges = 0;  ///< in three or more triangles
  size_t misoriented_edges = 0;   ///< an edge traversed twice in the same direction
  size_t degenerate_triangles = 0;  ///< repeated vertex or zero area
  double volume_m3 = 0;           ///< signed; positive when the triangles face outwards
  Eigen::Vector3d min_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d max_m = Eigen::Vector3d::Zero();

  bool watertight() const {
    return boundary_edges == 0 && non_manifold_edges == 0 && misoriented_edges == 0 && degenerate_triangles == 0;
  }
  Eigen::Vector3d size_m() const { return max_m - min_m; }
};

/// Precondition: mesh has at least one triangle and valid indices.
MeshTopologyReport CheckMeshTopology(const ColoredMesh& mesh);

}  // namespace mocap::sim
