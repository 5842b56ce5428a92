#pragma once
// Synthetic clouds with known geometry for the validator tests.
#include <random>

#include "core/camera.h"
#include "core/check.h"
#include "core/image.h"
#include "core/rigid3.h"
#include "validate/model_crop.h"
#include "validate/point_cloud.h"

namespace mocap::testing {

/// The Kinect v1-like camera of the frame tests.
inline PinholeCamera Kinect() { return PinholeCamera{640, 480, 525, 525, 319.5, 239.5, {}}; }

/// A depth frame and the label mask drawn with it.
struct Frame {
  DepthImage depth;
  LabelImage mask;
};

/// A closed box mesh (12 triangles) centred at the origin.
inline TriangleMesh BoxMesh(const Eigen::Vector3d& size_m) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.vertices.push_back(Eigen::Vector3d((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 0.5 : -0.5)
                                .cwiseProduct(size_m));
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& f : faces) {
    mesh.triangles.push_back({f[0], f[1], f[2]});
    mesh.triangles.push_back({f[0], f[2], f[3]});
  }
  return mesh;
}

/// Points on the surface of an axis-aligned box centred at the origin, on a grid of `spacing_m`.
inline PointCloud BoxSurface(const Eigen::Vector3d& size_m, double spacing_m) {
  PointCloud points;
  const Eigen::Vector3d half = size_m / 2;
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    const int na = static_cast<int>(size_m[a] / spacing_m), nb = static_cast<int>(size_m[b] / spacing_m);
    for (int side = -1; side <= 1; side += 2)
      for (int i = 0; i <= na; ++i)
        for (int j = 0; j <= nb; ++j) {
          Eigen::Vector3d p;
          p[axis] = side * half[axis];
          p[a] = -half[a] + i * size_m[a] / na;
          p[b] = -half[b] + j * size_m[b] / nb;
          points.push_back(p);
        }
  }
  return points;
}

/// A random rigid perturbation with translation norm `translation_m` and rotation angle `angle_deg`
/// about a random axis (fixed magnitudes, random directions).
inline Rigid3d RandomPerturbation(std::mt19937& rng, double translation_m, double angle_deg) {
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  const Eigen::Vector3d dir = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  return Rigid3d::FromRvec(axis * RadFromDeg(angle_deg), dir * translation_m);
}

inline PointCloud AddNoise(PointCloud points, std::mt19937& rng, double sigma_m) {
  std::normal_distribution<double> n(0.0, sigma_m);
  for (auto& p : points) p += Eigen::Vector3d(n(rng), n(rng), n(rng));
  return points;
}

}  // namespace mocap::testing
