#include "render/mesh_closure.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <numeric>
#include <utility>
#include <vector>

#include "core/check.h"

namespace mocap {
namespace {

/// Each vertex's representative: the first of the vertices at exactly its position.
std::vector<uint32_t> WeldByPosition(const std::vector<Eigen::Vector3f>& positions, int64_t& distinct) {
  std::vector<uint32_t> order(positions.size());
  std::iota(order.begin(), order.end(), 0u);
  auto less = [&](uint32_t a, uint32_t b) {
    const Eigen::Vector3f &p = positions[a], &q = positions[b];
    return std::tie(p.x(), p.y(), p.z(), a) < std::tie(q.x(), q.y(), q.z(), b);
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<uint32_t> weld(positions.size());
  distinct = 0;
  for (size_t i = 0; i < order.size(); ++i) {
    const bool same = i > 0 && positions[order[i]] == positions[order[i - 1]];
    weld[order[i]] = same ? weld[order[i - 1]] : order[i];
    distinct += same ? 0 : 1;
  }
  return weld;
}

uint32_t Root(std::vector<uint32_t>& parent, uint32_t v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];  // path halving
  return v;
}

/// An edge traversed by a triangle: the welded vertex pair (low, high) and whether it runs low -> high.
struct HalfEdge {
  uint64_t pair;
  bool forward;
  bool operator<(const HalfEdge& o) const { return std::tie(pair, forward) < std::tie(o.pair, o.forward); }
};

/// Counts boundary, misoriented and non-manifold edges from the sorted half-edges.
void ClassifyEdges(std::vector<HalfEdge>& half_edges, MeshClosure& closure) {
  std::sort(half_edges.begin(), half_edges.end());
  for (size_t i = 0; i < half_edges.size();) {
    size_t j = i;
    while (j < half_edges.size() && half_edges[j].pair == half_edges[i].pair) ++j;
    if (j - i == 1) ++closure.boundary_edges;
    else if (j - i > 2) ++closure.nonmanifold_edges;
    else if (half_edges[i].forward == half_edges[i + 1].forward) ++closure.misoriented_edges;
    i = j;
  }
}

/// Signed volume of each connected shell (`parent`: the union-find of the welded vertices), about the
/// first vertex so that the terms stay small for meshes far from their origin.
void SumShellVolumes(const Mesh& mesh, const std::vector<uint32_t>& weld, std::vector<uint32_t>& parent,
                     MeshClosure& closure) {
  const Eigen::Vector3d origin =
      mesh.positions_m.empty() ? Eigen::Vector3d(Eigen::Vector3d::Zero()) : Eigen::Vector3d(mesh.positions_m[0].cast<double>());
  std::vector<double> shell_volume(mesh.positions_m.size(), 0.0);
  std::vector<char> is_shell(mesh.positions_m.size(), 0);
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t a = weld[mesh.indices[t]], b = weld[mesh.indices[t + 1]], c = weld[mesh.indices[t + 2]];
    if (a == b || b == c || c == a) continue;
    const Eigen::Vector3d p = mesh.positions_m[a].cast<double>() - origin;
    const Eigen::Vector3d q = mesh.positions_m[b].cast<double>() - origin;
    const Eigen::Vector3d r = mesh.positions_m[c].cast<double>() - origin;
    const uint32_t shell = Root(parent, a);
    shell_volume[shell] += p.dot(q.cross(r)) / 6.0;
    is_shell[shell] = 1;
  }
  for (size_t s = 0; s < shell_volume.size(); ++s) {
    if (!is_shell[s]) continue;
    ++closure.shells;
    closure.inward_shells += shell_volume[s] > 0 ? 0 : 1;
    closure.volume_m3 += shell_volume[s];
  }
}

}  // namespace

bool MeshClosure::culling_exact() const {
  return triangles > 0 && boundary_edges == 0 && misoriented_edges == 0 && nonmanifold_edges == 0 &&
         inward_shells == 0;
}

std::string MeshClosure::Describe() const {
  if (culling_exact()) return Str("closed and outward, ", shells, " shell(s), volume ", volume_m3, " m^3");
  std::string why;
  auto add = [&why](int64_t n, const char* what) {
    if (n > 0) why += Str(why.empty() ? "" : ", ", n, " ", what);
  };
  add(boundary_edges, "boundary edges");
  add(misoriented_edges, "inconsistently wound edges");
  add(nonmanifold_edges, "edges in more than two triangles");
  add(inward_shells, "inward or flat shells");
  return why.empty() ? "no triangles" : why;
}

constexpr std::pair<BackFaceCulling, const char*> kCullingNames[] = {
    {BackFaceCulling::kNever, "never"}, {BackFaceCulling::kAuto, "auto"}, {BackFaceCulling::kAlways, "always"}};

BackFaceCulling BackFaceCullingFromString(const std::string& name) {
  for (const auto& [value, n] : kCullingNames)
    if (name == n) return value;
  throw InputError("back-face culling", Str("'", name, "' is not one of never, auto, always"));
}

const char* ToString(BackFaceCulling culling) {
  for (const auto& [value, n] : kCullingNames)
    if (value == culling) return n;
  return "?";
}

MeshClosure AnalyzeClosure(const Mesh& mesh) {
  MeshClosure closure;
  const std::vector<uint32_t> weld = WeldByPosition(mesh.positions_m, closure.welded_vertices);
  std::vector<uint32_t> parent(mesh.positions_m.size());
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(mesh.indices.size());
  std::vector<uint32_t> kept;  // first welded corner of each non-degenerate triangle
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t v[3] = {weld[mesh.indices[t]], weld[mesh.indices[t + 1]], weld[mesh.indices[t + 2]]};
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;  // no area: rasterises no pixel
    ++closure.triangles;
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = v[k], b = v[(k + 1) % 3];
      half_edges.push_back({(uint64_t{std::min(a, b)} << 32) | std::max(a, b), a < b});
      parent[Root(parent, a)] = Root(parent, b);
    }
  }
  ClassifyEdges(half_edges, closure);
  SumShellVolumes(mesh, weld, parent, closure);
  return closure;
}

}  // namespace mocap
