#pragma once
// Synthetic clouds with known geometry for the validator tests.
#include <cmath>
#include <functional>
#include <random>

#include "core/camera.h"
#include "core/check.h"
#include "core/image.h"
#include "core/rigid3.h"
#include "validate/model_crop.h"
#include "validate/point_cloud.h"
#include "validate/validate_options.h"

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

/// A closed elliptic cylinder (semi-axes a_m along x and b_m along y, height_m along z) centred at the
/// origin, `segments` facets around.
inline TriangleMesh EllipticCylinderMesh(double a_m, double b_m, double height_m, int segments = 96) {
  TriangleMesh mesh;
  for (int i = 0; i < segments; ++i) {
    const double t = 2 * M_PI * i / segments;
    for (const double z : {-0.5 * height_m, 0.5 * height_m}) mesh.vertices.push_back({a_m * std::cos(t), b_m * std::sin(t), z});
  }
  const int bottom = static_cast<int>(mesh.vertices.size()), top = bottom + 1;
  mesh.vertices.push_back({0, 0, -0.5 * height_m});
  mesh.vertices.push_back({0, 0, 0.5 * height_m});
  for (int i = 0; i < segments; ++i) {
    const int j = (i + 1) % segments;
    mesh.triangles.push_back({2 * i, 2 * j, 2 * j + 1});
    mesh.triangles.push_back({2 * i, 2 * j + 1, 2 * i + 1});
    mesh.triangles.push_back({bottom, 2 * j, 2 * i});
    mesh.triangles.push_back({top, 2 * i + 1, 2 * j + 1});
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

/// A slab x_m by y_m (a table top: its top face at z = 0, `thickness_m` thick) as triangles.
inline TriangleMesh Slab(double x_m, double y_m, double thickness_m) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.vertices.push_back({(i & 1 ? 0.5 : -0.5) * x_m, (i & 2 ? 0.5 : -0.5) * y_m, i & 4 ? 0.0 : -thickness_m});
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& f : faces) {
    mesh.triangles.push_back({f[0], f[1], f[2]});
    mesh.triangles.push_back({f[0], f[2], f[3]});
  }
  return mesh;
}

/// How far a surface point's range is pushed back along its ray (a time-of-flight camera's multipath),
/// metres, from the point in the model and camera frames; its pixel is kept.
using RangePush = std::function<double(const Eigen::Vector3d& p_model, const Eigen::Vector3d& p_camera)>;

/// Dense surface samples splatted with a nearest-depth test (the mesh seen by the camera), `noise_m`
/// noise; the mask holds 4 where the mesh is seen.
inline Frame SplatFrame(const TriangleMesh& mesh, const Rigid3d& T_camera_object, std::mt19937& rng,
                        const RangePush& push = {}, double noise_m = 0.001) {
  const PinholeCamera camera = Kinect();
  Frame f{DepthImage(640, 480, 0.0f), LabelImage(640, 480, 0)};
  for (const auto& p_model : SampleSurface(mesh, 0.0007)) {
    const Eigen::Vector3d p = T_camera_object * p_model;
    const auto px = camera.Project(p);
    if (!px) continue;
    const int u = static_cast<int>(std::lround(px->x())), v = static_cast<int>(std::lround(px->y()));
    if (!f.depth.contains(u, v) || (f.depth.at(u, v) != 0.0f && p.z() >= f.depth.at(u, v))) continue;
    f.depth.at(u, v) = static_cast<float>(push ? p.z() + push(p_model, p) * p.normalized().z() : p.z());
    f.mask.at(u, v) = 4;
  }
  if (!(noise_m > 0)) return f;
  std::normal_distribution<double> noise(0.0, noise_m);
  for (auto& d : f.depth.data)
    if (d > 0) d += static_cast<float>(noise(rng));
  return f;
}

/// The validator's defaults with crops of `pixel_m` (a table top's coarse crops).
inline ValidateOptions OptionsWithCropPixel(double pixel_m) {
  ValidateOptions options;
  options.crop.pixel_m = pixel_m;
  return options;
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
