#pragma once
// Point clouds of the validator: plain vectors of points in metres, in the frame named by the variable
// (`scene_camera`, `crop_model`). Helpers here do no I/O.
#include <Eigen/Core>
#include <vector>

#include "core/rigid3.h"

namespace mocap {

using PointCloud = std::vector<Eigen::Vector3d>;

/// Component-wise median (robust to segmentation outliers, the paper's acquisition seed).
/// Precondition: points non-empty.
Eigen::Vector3d ComponentMedian(const PointCloud& points);

/// Arithmetic mean. Precondition: points non-empty.
Eigen::Vector3d Centroid(const PointCloud& points);

/// T_a_b applied to every point of a cloud in frame b.
PointCloud Transform(const Rigid3d& T_a_b, const PointCloud& points_b);

/// One point (the centroid of the members) per occupied cubic voxel of edge `voxel_m`; `voxel_m <= 0`
/// returns the input unchanged. Output order follows the first occurrence of each voxel (deterministic).
PointCloud VoxelDownsample(const PointCloud& points, double voxel_m);

/// Axis-aligned box, metres.
struct Box3d {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(1.0);
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-1.0);
  bool empty() const { return (min.array() > max.array()).any(); }
  bool contains(const Eigen::Vector3d& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
};

/// Bounding box of the points grown by `margin_m` on every side (empty box for an empty cloud).
Box3d BoundingBox(const PointCloud& points, double margin_m = 0.0);

/// The scene points inside `box_model` (a box in the model frame) placed at T_scene_model: the
/// tracking-phase pruning of the paper ("removing points outside a bounding box of the latest
/// registered model pose").
PointCloud CropToBox(const PointCloud& scene, const Rigid3d& T_scene_model, const Box3d& box_model);

}  // namespace mocap
