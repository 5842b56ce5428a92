#pragma once
// Small robust statistics the calibration procedures share (the principal axes: core/principal_axes.h).
#include <span>
#include <vector>

#include <Eigen/Core>

#include "core/principal_axes.h"

namespace mocap {

/// The median (the upper one of an even count); 0 for no values.
double Median(std::vector<double> values);

/// 95 % half-width of the mean of `values` (in recording order), widened by their lag-1
/// autocorrelation (returned in `rho`, clamped to [0, 0.95]) with the AR(1) factor ArWidening(rho):
/// neighbouring frames see the same view and do not count as independent.
double MeanInterval95(std::span<const double> values, double& rho);

/// sqrt((1 + rho) / (1 - rho)): how much an AR(1) series with lag-1 autocorrelation rho widens the
/// standard error of its mean.
double ArWidening(double rho);

}  // namespace mocap
