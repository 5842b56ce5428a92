#include "core/principal_axes.h"

#include <Eigen/Eigenvalues>

namespace mocap {

PrincipalAxes PrincipalAxesOf(std::span<const Eigen::Vector3d> points) {
  PrincipalAxes out;
  for (const Eigen::Vector3d& p : points) out.centroid += p / static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) scatter += (p - out.centroid) * (p - out.centroid).transpose();
  out.axes = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors();  // ascending eigenvalues
  return out;
}

}  // namespace mocap
