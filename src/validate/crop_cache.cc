#include "validate/crop_cache.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "core/principal_axes.h"
#include "validate/point_grid.h"

namespace mocap {
namespace {

/// The cube-map cell of a unit direction: face (major axis and sign), then the face's (u, v) in
/// [-1, 1] split into `n` x `n` cells; `center` gets the cell's central direction. Cells are widest in
/// angle at a face's centre, so `n` is chosen from the step there.
int64_t DirectionCell(const Eigen::Vector3d& d, int n, Eigen::Vector3d* center) {
  int axis = 0;
  d.cwiseAbs().maxCoeff(&axis);
  const int face = 2 * axis + (d[axis] < 0 ? 1 : 0);
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  const auto cell = [n](double x) { return std::clamp(static_cast<int>((x + 1.0) * 0.5 * n), 0, n - 1); };
  const int iu = cell(d[a] / std::abs(d[axis])), iv = cell(d[b] / std::abs(d[axis]));
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  c[axis] = d[axis] < 0 ? -1.0 : 1.0;
  c[a] = (iu + 0.5) * 2.0 / n - 1.0;
  c[b] = (iv + 0.5) * 2.0 / n - 1.0;
  *center = c.normalized();
  return (static_cast<int64_t>(face) * n + iu) * n + iv;
}

}  // namespace

void CropCacheOptions::check() const {
  if (!(direction_step_deg > 0 && direction_step_deg <= 45))
    throw InputError("CropCacheOptions", "direction_step_deg must lie in (0, 45]");
  if (!(distance_ratio > 1 && distance_ratio <= 4)) throw InputError("CropCacheOptions", "distance_ratio must lie in (1, 4]");
  if (!(normal_radius_m > 0)) throw InputError("CropCacheOptions", "normal_radius_m must be positive");
}

PointCloud EstimateNormals(const PointCloud& points, double radius_m, const Eigen::Vector3d& toward_model) {
  const PointGrid grid(points);
  PointCloud normals(points.size());
  std::vector<std::pair<size_t, float>> near;
  std::vector<Eigen::Vector3d> neighbours;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d to_view = (toward_model - points[i]).normalized();
    grid.Radius(points[i], radius_m, &near);
    if (near.size() < 3) {
      normals[i] = to_view;
      continue;
    }
    neighbours.clear();
    for (const auto& [j, d2] : near) neighbours.push_back(grid.point(j));
    const Eigen::Vector3d n = PrincipalAxesOf(neighbours).axes.col(0);  // least spread: the normal
    normals[i] = n.dot(to_view) < 0 ? Eigen::Vector3d(-n) : n;
  }
  return normals;
}

CachedCropSource::CachedCropSource(const CropSource& base, const CropCacheOptions& options)
    : base_(base), options_((options.check(), options)) {
  const Box3d box = BoundingBox(base_.surface_model());
  center_model_ = 0.5 * (box.min + box.max);
  // A cube face spans 90 deg; its central cells are the widest (in angle), so they set the count.
  cells_per_edge_ = std::max(1, static_cast<int>(std::ceil(90.0 / options_.direction_step_deg)));
}

std::shared_ptr<const CachedCropSource::Cell> CachedCropSource::Compute(int64_t key, const Eigen::Vector3d& direction,
                                                                       double distance_m) const {
  auto cell = std::make_shared<Cell>();
  cell->eye_model = center_model_ + distance_m * direction;
  cell->points_model = base_.Crop(LookAt(cell->eye_model, center_model_, Eigen::Vector3d::UnitZ())).points_model;
  cell->view_direction_model = direction;
  std::lock_guard lock(mutex_);
  ++stats_.computed;
  return cells_.try_emplace(key, std::move(cell)).first->second;
}

std::shared_ptr<const CachedCropSource::Cell> CachedCropSource::Find(const Rigid3d& T_camera_model, ModelCrop* crop) const {
  crop->T_camera_model = T_camera_model;
  const Eigen::Vector3d eye_model = T_camera_model.inverse().translation();
  const Eigen::Vector3d offset = eye_model - center_model_;
  const double distance_m = offset.norm();
  if (!(distance_m > 1e-6)) {  // the camera inside the model: no view
    *crop = base_.Crop(T_camera_model);
    return nullptr;
  }
  Eigen::Vector3d direction;
  const int64_t cell = DirectionCell(offset / distance_m, cells_per_edge_, &direction);
  const double ratio_log = std::log(options_.distance_ratio);
  const int band = static_cast<int>(std::lround(std::log(distance_m) / ratio_log));
  const int64_t key = cell * 4096 + (band + 2048);
  std::shared_ptr<const Cell> found;
  {
    std::lock_guard lock(mutex_);
    ++stats_.requests;
    const auto it = cells_.find(key);
    if (it != cells_.end()) found = it->second;
  }
  if (!found) found = Compute(key, direction, std::exp(band * ratio_log));
  crop->points_model = found->points_model;
  crop->view_direction_model = found->view_direction_model;
  return found;
}

ModelCrop CachedCropSource::Crop(const Rigid3d& T_camera_model) const {
  ModelCrop crop;
  const std::shared_ptr<const Cell> cell = Find(T_camera_model, &crop);
  if (!cell) return crop;
  std::call_once(cell->normals_once, [&] {
    cell->normals_model = EstimateNormals(cell->points_model, options_.normal_radius_m, cell->eye_model);
  });
  crop.normals_model = cell->normals_model;
  return crop;
}

ModelCrop CachedCropSource::CropPoints(const Rigid3d& T_camera_model) const {
  ModelCrop crop;
  Find(T_camera_model, &crop);
  return crop;
}

CropCacheStats CachedCropSource::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace mocap
