#include "validate/frame_visibility.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/check.h"
#include "core/pinhole.h"

namespace mocap {

VisibleInFrameCropSource::VisibleInFrameCropSource(const CropSource& base, const PinholeCamera& camera,
                                                   const DepthImage& depth_m, const LabelImage& mask,
                                                   uint16_t label_id, double occluder_margin_m)
    : base_(base), camera_(camera), depth_m_(depth_m), mask_(mask), label_id_(label_id), margin_m_(occluder_margin_m) {
  MOCAP_CHECK(depth_m.width == camera.width && depth_m.height == camera.height, "depth and camera sizes differ");
  MOCAP_CHECK(mask.width == depth_m.width && mask.height == depth_m.height, "depth and mask sizes differ");
}

ModelCrop VisibleInFrameCropSource::Crop(const Rigid3d& T_camera_model) const {
  return Visible(T_camera_model, base_.Crop(T_camera_model));
}

ModelCrop VisibleInFrameCropSource::CropPoints(const Rigid3d& T_camera_model) const {
  return Visible(T_camera_model, base_.CropPoints(T_camera_model));
}

ModelCrop VisibleInFrameCropSource::Visible(const Rigid3d& T_camera_model, ModelCrop crop) const {
  PointCloud visible, normals;
  visible.reserve(crop.points_model.size());
  const bool has_normals = crop.normals_model.size() == crop.points_model.size();
  // The rotation as a matrix once per crop: applying the quaternion costs twice the arithmetic per point.
  const Eigen::Matrix3d R = T_camera_model.rotation_matrix();
  const Eigen::Vector3d t = T_camera_model.translation();
  const bool pinhole = !camera_.has_distortion();
  for (size_t i = 0; i < crop.points_model.size(); ++i) {
    const Eigen::Vector3d& p_model = crop.points_model[i];
    const Eigen::Vector3d p_camera = R * p_model + t;
    const auto pixel = NearestPixelOf(camera_, pinhole, p_camera);
    if (!pixel) continue;
    const int u = pixel->x(), v = pixel->y();
    if (!depth_m_.contains(u, v)) continue;  // outside the image: the frame cannot see it
    const float measured_m = depth_m_.at(u, v);
    const uint16_t owner = mask_.at(u, v);
    // A labelled pixel without depth (nearer than the sensor's range, dark, shiny): nothing there can
    // confirm or deny the point, which another object there may well hide. A depthless background pixel
    // still counts: a point moved onto it has left the object's outline.
    if (owner != 0 && !(measured_m > 0)) continue;
    const bool hidden = owner != label_id_ && measured_m > 0 && measured_m < p_camera.z() - margin_m_;
    if (hidden) continue;  // something else in front
    visible.push_back(p_model);
    if (has_normals) normals.push_back(crop.normals_model[i]);
  }
  crop.points_model = std::move(visible);
  crop.normals_model = std::move(normals);
  return crop;
}

namespace {

/// The label crop's nearest depth per square cell of `cell_px` pixels (+inf where none falls), and its
/// minimum over each cell's 3 x 3 neighbourhood, within the cells the crop covers plus one around.
class ModelDepthCells {
 public:
  ModelDepthCells(int width, int height, int cell_px)
      : cell_px_(cell_px), cols_((width + cell_px - 1) / cell_px), rows_((height + cell_px - 1) / cell_px),
        z_m_(static_cast<size_t>(cols_) * rows_, kNone) {}
  void Add(int u, int v, float z_m) {
    const int cx = u / cell_px_, cy = v / cell_px_;
    float& cell = z_m_[static_cast<size_t>(cy) * cols_ + cx];
    cell = std::min(cell, z_m);
    lo_x_ = std::min(lo_x_, cx), hi_x_ = std::max(hi_x_, cx), lo_y_ = std::min(lo_y_, cy), hi_y_ = std::max(hi_y_, cy);
  }
  /// Replaces each cell by the minimum of its neighbourhood; call once, after the last Add.
  void Spread() {
    lo_x_ = std::max(0, lo_x_ - 1), hi_x_ = std::min(cols_ - 1, hi_x_ + 1);
    lo_y_ = std::max(0, lo_y_ - 1), hi_y_ = std::min(rows_ - 1, hi_y_ + 1);
    std::vector<float> spread(z_m_.size(), kNone);
    for (int cy = lo_y_; cy <= hi_y_; ++cy)
      for (int cx = lo_x_; cx <= hi_x_; ++cx) {
        float nearest = kNone;
        for (int y = std::max(0, cy - 1); y <= std::min(rows_ - 1, cy + 1); ++y)
          for (int x = std::max(0, cx - 1); x <= std::min(cols_ - 1, cx + 1); ++x)
            nearest = std::min(nearest, z_m_[static_cast<size_t>(y) * cols_ + x]);
        spread[static_cast<size_t>(cy) * cols_ + cx] = nearest;
      }
    z_m_ = std::move(spread);
  }
  /// The nearest model depth about cell (cx, cy), after Spread; +inf where none.
  float At(int cx, int cy) const { return z_m_[static_cast<size_t>(cy) * cols_ + cx]; }
  /// The covered cells and one around them (after Spread): [lo_x, hi_x] x [lo_y, hi_y]; empty before any Add.
  int lo_x() const { return lo_x_; }
  int hi_x() const { return hi_x_; }
  int lo_y() const { return lo_y_; }
  int hi_y() const { return hi_y_; }
  int cell_px() const { return cell_px_; }

 private:
  static constexpr float kNone = std::numeric_limits<float>::infinity();
  int cell_px_, cols_, rows_;
  std::vector<float> z_m_;
  int lo_x_ = std::numeric_limits<int>::max(), hi_x_ = -1, lo_y_ = std::numeric_limits<int>::max(), hi_y_ = -1;
};

struct ProjectedPoint {
  int u, v;
  float z_m;
};

/// The crop's points in the image (camera frame depth), those that land in it.
std::vector<ProjectedPoint> ProjectCrop(const ModelCrop& crop, const PinholeCamera& camera) {
  std::vector<ProjectedPoint> projected;
  projected.reserve(crop.points_model.size());
  const Eigen::Matrix3d R = crop.T_camera_model.rotation_matrix();  // once, not a quaternion per point
  const Eigen::Vector3d t = crop.T_camera_model.translation();
  for (const Eigen::Vector3d& p_model : crop.points_model) {
    const Eigen::Vector3d p_camera = R * p_model + t;
    const auto pixel = camera.Project(p_camera);
    if (!pixel) continue;
    const int u = NearestPixel(pixel->x()), v = NearestPixel(pixel->y());
    if (u >= 0 && v >= 0 && u < camera.width && v < camera.height)
      projected.push_back({u, v, static_cast<float>(p_camera.z())});
  }
  return projected;
}

}  // namespace

std::optional<OccluderCut> CutOccluders(const DepthImage& depth_m, const PinholeCamera& camera, const LabelImage& mask,
                                        uint16_t label_id, const ModelCrop& label_crop, double crop_pixel_m,
                                        double margin_m) {
  MOCAP_CHECK(depth_m.width == camera.width && depth_m.height == camera.height, "depth and camera sizes differ");
  MOCAP_CHECK(mask.width == depth_m.width && mask.height == depth_m.height, "depth and mask sizes differ");
  const std::vector<ProjectedPoint> projected = ProjectCrop(label_crop, camera);
  if (projected.empty()) return std::nullopt;
  float nearest_m = std::numeric_limits<float>::infinity();
  for (const ProjectedPoint& p : projected) nearest_m = std::min(nearest_m, p.z_m);
  const int cell_px = std::clamp(static_cast<int>(std::ceil(crop_pixel_m * camera.fx / nearest_m)), 1, 64);
  ModelDepthCells cells(camera.width, camera.height, cell_px);
  for (const ProjectedPoint& p : projected) cells.Add(p.u, p.v, p.z_m);
  cells.Spread();
  std::optional<OccluderCut> cut;
  const int cell = cells.cell_px();
  for (int v = cells.lo_y() * cell; v < std::min(camera.height, (cells.hi_y() + 1) * cell); ++v)
    for (int cx = cells.lo_x(); cx <= cells.hi_x(); ++cx) {  // a run of pixels per cell: one model depth
      const float model_m = cells.At(cx, v / cell);
      if (!std::isfinite(model_m)) continue;  // no crop point about these pixels: nothing to compare
      const float limit_m = model_m - static_cast<float>(margin_m);
      for (int u = cx * cell; u < std::min(camera.width, (cx + 1) * cell); ++u) {
        if (mask.at(u, v) != label_id) continue;
        const float measured_m = depth_m.at(u, v);
        if (!(measured_m > 0) || !(measured_m < limit_m)) continue;
        if (!cut) cut = OccluderCut{mask, 0};
        cut->mask.at(u, v) = 0;
        ++cut->pixels;
      }
    }
  return cut;
}

}  // namespace mocap
