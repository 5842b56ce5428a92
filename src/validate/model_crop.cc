#include "validate/model_crop.h"

#include <cmath>
#include <numbers>
#include <unordered_map>

#include "core/check.h"

namespace mocap {

void TriangleMesh::check() const {
  if (vertices.empty() || triangles.empty()) throw InputError("TriangleMesh", "mesh has no vertices or triangles");
  const int n = static_cast<int>(vertices.size());
  for (size_t i = 0; i < triangles.size(); ++i)
    if ((triangles[i].array() < 0).any() || (triangles[i].array() >= n).any())
      throw InputError(Str("TriangleMesh triangle ", i), Str("vertex index out of range [0, ", n, ")"));
}

PointCloud SampleSurface(const TriangleMesh& mesh, double spacing_m) {
  mesh.check();
  MOCAP_CHECK(spacing_m > 0, "spacing must be positive");
  PointCloud points;
  for (const auto& tri : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[tri[0]];
    const Eigen::Vector3d& b = mesh.vertices[tri[1]];
    const Eigen::Vector3d& c = mesh.vertices[tri[2]];
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, static_cast<int>(std::ceil(longest / spacing_m)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
        points.push_back(a + u * (b - a) + v * (c - a));
      }
  }
  return points;
}

void CropOptions::check() const {
  if (!(pixel_m > 0)) throw InputError("CropOptions", "pixel_m must be positive");
}

SurfaceCropSource::SurfaceCropSource(PointCloud surface_model, const CropOptions& options)
    : surface_(std::move(surface_model)), options_(options) {
  options_.check();
  if (surface_.empty()) throw InputError("SurfaceCropSource", "model has no surface points");
  center_model_ = Centroid(surface_);
}

SurfaceCropSource SurfaceCropSource::FromMesh(const TriangleMesh& mesh, const CropOptions& options) {
  options.check();
  return SurfaceCropSource(SampleSurface(mesh, options.pixel_m / 2), options);
}

ModelCrop SurfaceCropSource::Crop(const Rigid3d& T_camera_model) const {
  ModelCrop crop;
  crop.T_camera_model = T_camera_model;
  const Eigen::Vector3d eye_model = T_camera_model.inverse().translation();
  crop.view_direction_model = eye_model.normalized();
  // Focal length so that a pixel spans pixel_m at the depth of the model centre.
  const double depth_m = (T_camera_model * center_model_).z();
  if (!(depth_m > 1e-6)) return crop;  // model behind or at the camera: nothing is visible
  const double f = depth_m / options_.pixel_m;
  const Eigen::Matrix3d R = T_camera_model.rotation_matrix();
  const Eigen::Vector3d t = T_camera_model.translation();
  // Per pixel: the sample index with the smallest depth.
  struct Best { float z; int index; };
  std::unordered_map<int64_t, Best> zbuffer;
  zbuffer.reserve(surface_.size() / 2);
  std::vector<int64_t> pixel_of(surface_.size(), -1);
  for (size_t i = 0; i < surface_.size(); ++i) {
    const Eigen::Vector3d p = R * surface_[i] + t;
    if (p.z() <= 1e-6) continue;
    const auto u = static_cast<int64_t>(std::floor(f * p.x() / p.z()));
    const auto v = static_cast<int64_t>(std::floor(f * p.y() / p.z()));
    const int64_t key = (u + (1 << 20)) | ((v + (1 << 20)) << 21);
    pixel_of[i] = key;
    const Best candidate{static_cast<float>(p.z()), static_cast<int>(i)};
    auto [it, inserted] = zbuffer.try_emplace(key, candidate);
    if (!inserted && candidate.z < it->second.z) it->second = candidate;
  }
  // One point per pixel: the nearest sample, i.e. the front surface, in sample order (deterministic).
  crop.points_model.reserve(zbuffer.size());
  for (size_t i = 0; i < surface_.size(); ++i) {
    if (pixel_of[i] < 0) continue;
    const Best& best = zbuffer.at(pixel_of[i]);
    if (best.index == static_cast<int>(i)) crop.points_model.push_back(surface_[i]);
  }
  return crop;
}

Rigid3d LookAt(const Eigen::Vector3d& eye_model, const Eigen::Vector3d& target_model, const Eigen::Vector3d& up_model) {
  const Eigen::Vector3d z = (target_model - eye_model).normalized();
  Eigen::Vector3d up = up_model.normalized();
  if (std::abs(z.dot(up)) > 0.99) up = std::abs(z.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d x = z.cross(-up).normalized();  // image y points down, against `up`
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R_model_camera;
  R_model_camera << x, y, z;
  return Rigid3d(R_model_camera, eye_model).inverse();
}

std::vector<Rigid3d> ViewSpherePoses(int count, double min_elevation_deg, double max_elevation_deg,
                                     const Eigen::Vector3d& center_model, double distance_m) {
  MOCAP_CHECK(count >= 1 && min_elevation_deg <= max_elevation_deg, "bad view sphere");
  std::vector<Rigid3d> poses;
  const double z_lo = std::sin(RadFromDeg(min_elevation_deg)), z_hi = std::sin(RadFromDeg(max_elevation_deg));
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    // Equal-area lattice: uniform in sin(elevation), golden-angle steps in azimuth.
    const double z = z_lo + (z_hi - z_lo) * (i + 0.5) / count;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double azimuth = golden * i;
    const Eigen::Vector3d dir(r * std::cos(azimuth), r * std::sin(azimuth), z);
    poses.push_back(LookAt(center_model + distance_m * dir, center_model, Eigen::Vector3d::UnitZ()));
  }
  return poses;
}

}  // namespace mocap
