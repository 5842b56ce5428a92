#include "sim/mesh_builder.h"

#include <cmath>
#include <numbers>

#include "core/check.h"

namespace mocap::sim {
namespace {

double SignedPow(double value, double exponent) {
  return std::copysign(std::pow(std::abs(value), exponent), value);
}

bool IsPole(const LatheRing& ring) { return ring.rx_m == 0.0 && ring.ry_m == 0.0; }

double SignedVolume(const ColoredMesh& mesh, size_t first_triangle) {
  double volume = 0;
  for (size_t t = first_triangle; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    volume += mesh.positions_m[tri[0]].dot(mesh.positions_m[tri[1]].cross(mesh.positions_m[tri[2]])) / 6.0;
  }
  return volume;
}

}  // namespace

uint32_t MeshBuilder::AddVertex(const Eigen::Vector3d& p, Rgb8 color) {
  mesh_.positions_m.push_back(p);
  mesh_.colors.push_back(color);
  return static_cast<uint32_t>(mesh_.positions_m.size() - 1);
}

void MeshBuilder::AddQuad(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
  mesh_.triangles.push_back({a, b, c});
  mesh_.triangles.push_back({a, c, d});
}

void MeshBuilder::OrientShell(size_t first_triangle) {
  if (SignedVolume(mesh_, first_triangle) >= 0) return;
  for (size_t t = first_triangle; t < mesh_.triangles.size(); ++t) std::swap(mesh_.triangles[t][1], mesh_.triangles[t][2]);
}

void MeshBuilder::AddLathe(const std::vector<LatheRing>& rings, int segments, const Rigid3d& T_mesh_shell) {
  MOCAP_CHECK(rings.size() >= 2 && segments >= 3, "lathe needs 2 rings and 3 segments");
  const size_t first_triangle = mesh_.triangles.size();
  const bool bottom_pole = IsPole(rings.front());
  const bool top_pole = IsPole(rings.back());
  MOCAP_CHECK(bottom_pole == top_pole, "a lathe has poles at both ends or at neither");
  const size_t ring_begin = bottom_pole ? 1 : 0;
  const size_t ring_end = top_pole ? rings.size() - 1 : rings.size();
  MOCAP_CHECK(ring_end > ring_begin, "a lathe needs a ring between its poles");

  std::vector<uint32_t> ring_start;
  for (size_t i = ring_begin; i < ring_end; ++i) {
    const LatheRing& ring = rings[i];
    MOCAP_CHECK(!IsPole(ring), "pole inside a lathe profile");
    ring_start.push_back(static_cast<uint32_t>(mesh_.positions_m.size()));
    for (int j = 0; j < segments; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / segments;
      const double e = 2.0 / ring.exponent;
      const Eigen::Vector3d p(ring.cx_m + ring.rx_m * SignedPow(std::cos(phi), e),
                              ring.cy_m + ring.ry_m * SignedPow(std::sin(phi), e), ring.z_m);
      AddVertex(T_mesh_shell * p, ring.color);
    }
  }
  const auto n = static_cast<uint32_t>(segments);
  auto at = [&](size_t ring, uint32_t j) { return ring_start[ring] + (j % n); };
  const size_t ring_count = ring_start.size();
  const size_t bands = bottom_pole ? ring_count - 1 : ring_count;  // a tube closes last onto first
  for (size_t i = 0; i < bands; ++i) {
    const size_t next = (i + 1) % ring_count;
    for (uint32_t j = 0; j < n; ++j) AddQuad(at(i, j), at(i, j + 1), at(next, j + 1), at(next, j));
  }
  if (bottom_pole) {
    const LatheRing& b = rings.front();
    const uint32_t pole = AddVertex(T_mesh_shell * Eigen::Vector3d(b.cx_m, b.cy_m, b.z_m), b.color);
    for (uint32_t j = 0; j < n; ++j) mesh_.triangles.push_back({pole, at(0, j + 1), at(0, j)});
    const LatheRing& t = rings.back();
    const uint32_t top = AddVertex(T_mesh_shell * Eigen::Vector3d(t.cx_m, t.cy_m, t.z_m), t.color);
    for (uint32_t j = 0; j < n; ++j) mesh_.triangles.push_back({top, at(ring_count - 1, j), at(ring_count - 1, j + 1)});
  }
  OrientShell(first_triangle);
}

void MeshBuilder::AddCylinder(double radius_m, double z0_m, double z1_m, int segments, Rgb8 color,
                              const Rigid3d& T_mesh_shell) {
  MOCAP_CHECK(radius_m > 0 && z1_m > z0_m, "degenerate cylinder");
  AddLathe({{z0_m, 0, 0, 2, 0, 0, color},
            {z0_m, radius_m, radius_m, 2, 0, 0, color},
            {z1_m, radius_m, radius_m, 2, 0, 0, color},
            {z1_m, 0, 0, 2, 0, 0, color}},
           segments, T_mesh_shell);
}

void MeshBuilder::AddBox(const Eigen::Vector3d& half_extents_m, Rgb8 color, const Rigid3d& T_mesh_shell) {
  MOCAP_CHECK((half_extents_m.array() > 0).all(), "degenerate box");
  const size_t first_triangle = mesh_.triangles.size();
  uint32_t v[8];
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d corner((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    v[i] = AddVertex(T_mesh_shell * Eigen::Vector3d(corner.cwiseProduct(half_extents_m)), color);
  }
  // Faces listed counter-clockwise seen from outside (-z, +z, -y, +y, -x, +x).
  AddQuad(v[0], v[2], v[3], v[1]);
  AddQuad(v[4], v[5], v[7], v[6]);
  AddQuad(v[0], v[1], v[5], v[4]);
  AddQuad(v[2], v[6], v[7], v[3]);
  AddQuad(v[0], v[4], v[6], v[2]);
  AddQuad(v[1], v[3], v[7], v[5]);
  OrientShell(first_triangle);
}

void MeshBuilder::AddClosedTube(const std::vector<Eigen::Vector3d>& path_m, double radius_m, int segments,
                                Rgb8 color, const Rigid3d& T_mesh_shell) {
  MOCAP_CHECK(path_m.size() >= 3 && segments >= 3 && radius_m > 0, "degenerate tube");
  const size_t first_triangle = mesh_.triangles.size();
  const size_t count = path_m.size();
  // The plane normal of the (planar) loop is the binormal of every cross-section.
  Eigen::Vector3d plane_normal = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < count; ++i) plane_normal += path_m[i].cross(path_m[(i + 1) % count]);
  MOCAP_CHECK(plane_normal.norm() > 0, "tube path encloses no area");
  plane_normal.normalize();
  std::vector<uint32_t> ring_start;
  for (size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d tangent = (path_m[(i + 1) % count] - path_m[(i + count - 1) % count]).normalized();
    const Eigen::Vector3d normal = plane_normal.cross(tangent).normalized();
    ring_start.push_back(static_cast<uint32_t>(mesh_.positions_m.size()));
    for (int j = 0; j < segments; ++j) {
      const double a = 2.0 * std::numbers::pi * j / segments;
      AddVertex(T_mesh_shell * Eigen::Vector3d(path_m[i] + radius_m * (std::cos(a) * normal + std::sin(a) * plane_normal)),
                color);
    }
  }
  const auto n = static_cast<uint32_t>(segments);
  for (size_t i = 0; i < count; ++i) {
    const size_t next = (i + 1) % count;
    for (uint32_t j = 0; j < n; ++j)
      AddQuad(ring_start[i] + j, ring_start[i] + (j + 1) % n, ring_start[next] + (j + 1) % n, ring_start[next] + j);
  }
  OrientShell(first_triangle);
}

}  // namespace mocap::sim
