#pragma once
// Small robust statistics the calibration procedures share, and the principal axes of a point set.
#include <span>
#include <vector>

#include <Eigen/Core>

namespace mocap {

/// The median (the upper one of an even count); 0 for no values.
double Median(std::vector<double> values);

/// 95 % half-width of the mean of `values` (in recording order), widened by their lag-1
/// autocorrelation (returned in `rho`, clamped to [0, 0.95]) with the AR(1) factor ArWidening(rho):
/// neighbouring frames see the same view and do not count as independent.
double MeanInterval95(std::span<const double> values, double& rho);

/// Centroid and principal axes of a point set: the columns of `axes` by ascending spread, so col(0) is
/// the normal of the least-squares plane through `centroid` and col(2) the direction of largest spread.
struct PrincipalAxes {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
};
PrincipalAxes PrincipalAxesOf(std::span<const Eigen::Vector3d> points);

/// sqrt((1 + rho) / (1 - rho)): how much an AR(1) series with lag-1 autocorrelation rho widens the
/// standard error of its mean.
double ArWidening(double rho);

}  // namespace mocap
