#include "sim/mesh_check.h"

#include <map>
#include <utility>

#include "core/check.h"

namespace mocap::sim {

MeshTopologyReport CheckMeshTopology(const ColoredMesh& mesh) {
  MOCAP_CHECK(!mesh.triangles.empty(), "mesh without triangles");
  MeshTopologyReport report;
  report.min_m = report.max_m = mesh.positions_m.front();
  for (const auto& p : mesh.positions_m) {
    report.min_m = report.min_m.cwiseMin(p);
    report.max_m = report.max_m.cwiseMax(p);
  }
  // Directed edge counts, keyed by (from, to).
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const auto& tri : mesh.triangles) {
    for (uint32_t index : tri) MOCAP_CHECK(index < mesh.positions_m.size(), "triangle index out of range");
    const Eigen::Vector3d& a = mesh.positions_m[tri[0]];
    const Eigen::Vector3d& b = mesh.positions_m[tri[1]];
    const Eigen::Vector3d& c = mesh.positions_m[tri[2]];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] || (b - a).cross(c - a).norm() <= 1e-14)
      ++report.degenerate_triangles;
    report.volume_m3 += a.dot(b.cross(c)) / 6.0;
    for (int k = 0; k < 3; ++k) ++directed[{tri[k], tri[(k + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    const int reverse_count = reverse == directed.end() ? 0 : reverse->second;
    if (count > 1) ++report.misoriented_edges;
    if (edge.first > edge.second && reverse_count > 0) continue;  // counted from the other direction
    ++report.edges;
    const int total = count + reverse_count;
    if (total == 1) ++report.boundary_edges;
    if (total > 2) ++report.non_manifold_edges;
  }
  return report;
}

}  // namespace mocap::sim
