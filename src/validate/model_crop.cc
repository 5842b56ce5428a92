#include "validate/model_crop.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <unordered_map>
#include <vector>

#include "core/check.h"
#include "validate/first_seen_index.h"

namespace mocap {
namespace {

/// std::llround without the libm call (x86-64 without SSE4.1 does not inline it; sampling a table top
/// rounds three coordinates per sample). Exact for |x| < 2^52.
int64_t RoundHalfAway(double x) {
  const auto whole = static_cast<int64_t>(x);  // toward zero
  const double rest = x - static_cast<double>(whole);
  return whole + (rest >= 0.5) - (rest <= -0.5);
}

struct LatticeHash {
  uint64_t operator()(const std::array<int64_t, 3>& k) const {
    uint64_t h = 0;
    for (const int64_t x : k) h = MixBits(h ^ static_cast<uint64_t>(x));
    return h;
  }
};

}  // namespace

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
  // Triangles share vertices and edges: a vertex of six triangles would be sampled six times. Samples
  // within 10 um of an earlier one are the same surface point and are kept once; the z-buffer's work
  // is per sample.
  FirstSeenIndex<std::array<int64_t, 3>, LatticeHash> seen;  // positions on a 10 um lattice
  const auto add = [&](const Eigen::Vector3d& p) {
    if (seen.Insert({RoundHalfAway(p.x() * 1e5), RoundHalfAway(p.y() * 1e5), RoundHalfAway(p.z() * 1e5)}).second)
      points.push_back(p);
  };
  const auto steps = [spacing_m](const Eigen::Vector3d& edge) {
    return std::max(1, static_cast<int>(std::ceil(edge.norm() / spacing_m)));
  };
  for (const auto& tri : mesh.triangles) {
    // The grid runs along the two edges at the vertex opposite the longest edge, each at its own step
    // count, so a long thin triangle gets samples in proportion to its area (one count from the longest
    // edge for both directions put millions of samples on the slivers of a cylinder's side).
    int k = 0;
    double longest = -1.0;
    for (int e = 0; e < 3; ++e) {
      const double length = (mesh.vertices[tri[(e + 1) % 3]] - mesh.vertices[tri[(e + 2) % 3]]).norm();
      if (length > longest) longest = length, k = e;
    }
    const Eigen::Vector3d& a = mesh.vertices[tri[k]];
    const Eigen::Vector3d& b = mesh.vertices[tri[(k + 1) % 3]];
    const Eigen::Vector3d& c = mesh.vertices[tri[(k + 2) % 3]];
    const int n1 = steps(b - a), n2 = steps(c - a), n3 = steps(c - b);
    for (int i = 0; i <= n1; ++i)
      for (int j = 0; i * n2 + j * n1 <= n1 * n2; ++j)
        add(a + (static_cast<double>(i) / n1) * (b - a) + (static_cast<double>(j) / n2) * (c - a));
    for (int i = 0; i <= n3; ++i) add(b + (static_cast<double>(i) / n3) * (c - b));  // the long edge itself
  }
  return points;
}

void CropOptions::check() const {
  if (!(pixel_m > 0)) throw InputError("CropOptions", "pixel_m must be positive");
  if (max_points < 100) throw InputError("CropOptions", "max_points must be >= 100");
}

SurfaceCropSource::SurfaceCropSource(PointCloud surface_model, const CropOptions& options)
    : surface_(std::move(surface_model)), options_(options) {
  options_.check();
  if (surface_.empty()) throw InputError("SurfaceCropSource", "model has no surface points");
  center_model_ = Centroid(surface_);
  box_model_ = BoundingBox(surface_);
}

SurfaceCropSource SurfaceCropSource::FromMesh(const TriangleMesh& mesh, const CropOptions& options) {
  options.check();
  return SurfaceCropSource(SampleSurface(mesh, options.pixel_m / 2), options);
}

namespace {

/// std::floor without the libm call (x86-64 without SSE4.1 does not inline it): this loop runs once per
/// surface sample and crop. Values beyond the int64 range are returned unchanged (rejected as pixels).
double Floor(double x) {
  if (!(std::abs(x) < 1e15)) return x;
  const auto i = static_cast<int64_t>(x);
  return static_cast<double>(x < static_cast<double>(i) ? i - 1 : i);
}

/// Pixel keys of the virtual camera: dense (row-major over the pixel rectangle the model can cover)
/// when that rectangle is small, else (u, v) packed into 21 bits each (any pixel in range).
struct PixelGrid {
  Eigen::Vector2i origin = Eigen::Vector2i::Constant(-(1 << 20));
  int64_t width = int64_t{1} << 21, height = int64_t{1} << 21;
  bool dense = false;
  /// -1 for a pixel outside the grid.
  int64_t Key(double u, double v) const {
    const double du = u - origin.x(), dv = v - origin.y();
    if (!(du >= 0 && dv >= 0 && du < static_cast<double>(width) && dv < static_cast<double>(height))) return -1;
    return static_cast<int64_t>(dv) * width + static_cast<int64_t>(du);
  }
};

/// The dense grid over the projections of the model's bounding-box corners (a box wholly in front of
/// the camera projects inside their hull), or the packed one when a corner is not in front or the
/// rectangle would be much larger than the sample count.
PixelGrid GridFor(const Box3d& box_model, const Rigid3d& T_camera_model, double focal_px, size_t samples) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = Eigen::Vector2d::Constant(-1e300);
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d corner((c & 1 ? box_model.max : box_model.min).x(), (c & 2 ? box_model.max : box_model.min).y(),
                                 (c & 4 ? box_model.max : box_model.min).z());
    const Eigen::Vector3d p = T_camera_model * corner;
    if (p.z() <= 1e-6) return {};
    const Eigen::Vector2d uv(Floor(focal_px * p.x() / p.z()), Floor(focal_px * p.y() / p.z()));
    lo = lo.cwiseMin(uv);
    hi = hi.cwiseMax(uv);
  }
  const Eigen::Vector2d size = hi - lo + Eigen::Vector2d::Ones();
  if (!(size.x() * size.y() <= 16.0 * static_cast<double>(samples) + 4096)) return {};
  PixelGrid grid;
  grid.origin = lo.cast<int>();
  grid.width = static_cast<int64_t>(size.x());
  grid.height = static_cast<int64_t>(size.y());
  grid.dense = true;
  return grid;
}

/// Per pixel key, the nearest sample offered so far.
class ZBuffer {
 public:
  explicit ZBuffer(const PixelGrid& grid) : dense_(grid.dense) {
    if (dense_) image_.assign(static_cast<size_t>(grid.width * grid.height), Best{0.0f, -1});
  }
  void Offer(int64_t key, float z, int index) {
    Best& best = dense_ ? image_[static_cast<size_t>(key)] : sparse_.try_emplace(key, Best{z, index}).first->second;
    if (best.index < 0 || z < best.z) best = Best{z, index};
  }
  int Winner(int64_t key) const { return dense_ ? image_[static_cast<size_t>(key)].index : sparse_.at(key).index; }

 private:
  struct Best { float z; int index; };
  bool dense_;
  std::vector<Best> image_;
  std::unordered_map<int64_t, Best> sparse_;
};

}  // namespace

ModelCrop SurfaceCropSource::Crop(const Rigid3d& T_camera_model) const {
  ModelCrop crop;
  crop.T_camera_model = T_camera_model;
  const Eigen::Vector3d eye_model = T_camera_model.inverse().translation();
  crop.view_direction_model = eye_model.normalized();
  // Focal length so that a pixel spans pixel_m at the depth of the model centre.
  const double depth_m = (T_camera_model * center_model_).z();
  if (!(depth_m > 1e-6)) return crop;  // model behind or at the camera: nothing is visible
  const double f = depth_m / options_.pixel_m;
  const PixelGrid grid = GridFor(box_model_, T_camera_model, f, surface_.size());
  const Eigen::Matrix3d R = T_camera_model.rotation_matrix();
  const Eigen::Vector3d t = T_camera_model.translation();
  ZBuffer zbuffer(grid);
  std::vector<int64_t> pixel_of(surface_.size(), -1);
  for (size_t i = 0; i < surface_.size(); ++i) {
    const Eigen::Vector3d p = R * surface_[i] + t;
    if (p.z() <= 1e-6) continue;
    const double scale = f / p.z();
    pixel_of[i] = grid.Key(Floor(scale * p.x()), Floor(scale * p.y()));
    if (pixel_of[i] >= 0) zbuffer.Offer(pixel_of[i], static_cast<float>(p.z()), static_cast<int>(i));
  }
  // One point per pixel: the nearest sample, i.e. the front surface, in sample order (deterministic).
  for (size_t i = 0; i < surface_.size(); ++i)
    if (pixel_of[i] >= 0 && zbuffer.Winner(pixel_of[i]) == static_cast<int>(i)) crop.points_model.push_back(surface_[i]);
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
