#include "render/primitives.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/check.h"

namespace mocap {

Mesh MakeBoxMesh(const Eigen::Vector3d& size_m) {
  Mesh mesh;
  mesh.source = "generated box";
  const Eigen::Vector3f h = (size_m / 2).cast<float>();
  for (int i = 0; i < 8; ++i)
    mesh.positions_m.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  // Two triangles per face, counter-clockwise seen from outside; corner index bits are (x, y, z).
  const uint32_t faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& f : faces) mesh.indices.insert(mesh.indices.end(), {f[0], f[1], f[2], f[0], f[2], f[3]});
  return mesh;
}

Mesh MakeDiscMesh(double radius_m, int segments) {
  MOCAP_CHECK(segments >= 3 && radius_m > 0, "disc with ", segments, " segments, radius ", radius_m);
  Mesh mesh;
  mesh.source = "generated disc";
  mesh.positions_m.emplace_back(0.0f, 0.0f, 0.0f);
  for (int i = 0; i < segments; ++i) {
    const double a = 2 * std::numbers::pi * i / segments;
    mesh.positions_m.emplace_back(static_cast<float>(radius_m * std::cos(a)), static_cast<float>(radius_m * std::sin(a)), 0.0f);
    mesh.indices.insert(mesh.indices.end(), {0u, static_cast<uint32_t>(1 + i), static_cast<uint32_t>(1 + (i + 1) % segments)});
  }
  return mesh;
}

Mesh MakeRectangleMesh(double width_m, double height_m) {
  Mesh mesh;
  mesh.source = "generated rectangle";
  const auto w = static_cast<float>(width_m / 2), h = static_cast<float>(height_m / 2);
  mesh.positions_m = {{-w, -h, 0}, {w, -h, 0}, {w, h, 0}, {-w, h, 0}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return mesh;
}

Mesh MakeSphereMesh(double radius_m, int triangles) {
  // rings * segments * 2 triangles (poles included as degenerate quads' halves); segments = 2 * rings.
  const int rings = std::max(4, static_cast<int>(std::lround(std::sqrt(triangles / 4.0))));
  const int segments = 2 * rings;
  Mesh mesh;
  mesh.source = "generated sphere";
  for (int r = 0; r <= rings; ++r) {
    const double theta = std::numbers::pi * r / rings;
    // Exactly 0 at the poles (sin(pi) is 1.2e-16), so each pole ring is one position and the sphere is
    // closed once vertices are welded (mesh_closure.h).
    const double sin_theta = (r == 0 || r == rings) ? 0.0 : std::sin(theta);
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * std::numbers::pi * s / segments;
      mesh.positions_m.emplace_back(static_cast<float>(radius_m * sin_theta * std::cos(phi)),
                                    static_cast<float>(radius_m * sin_theta * std::sin(phi)),
                                    static_cast<float>(radius_m * std::cos(theta)));
    }
  }
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      const auto a = static_cast<uint32_t>(r * segments + s), b = static_cast<uint32_t>(r * segments + (s + 1) % segments);
      const auto c = a + static_cast<uint32_t>(segments), d = b + static_cast<uint32_t>(segments);
      mesh.indices.insert(mesh.indices.end(), {a, c, b, b, c, d});
    }
  }
  return mesh;
}

}  // namespace mocap
