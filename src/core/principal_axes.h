#pragma once
// The principal axes of a point set: plane and normal fits for the calibration procedures (tag planes,
// board planes) and the validator (surface normals of model crops).
#include <span>

#include <Eigen/Core>

namespace mocap {

/// Centroid and principal axes of a point set: the columns of `axes` by ascending spread, so col(0) is
/// the normal of the least-squares plane through `centroid` and col(2) the direction of largest spread.
struct PrincipalAxes {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
};
PrincipalAxes PrincipalAxesOf(std::span<const Eigen::Vector3d> points);

}  // namespace mocap
