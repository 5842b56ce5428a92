#include "calibrate/robust_stats.h"

#include <algorithm>
#include <cmath>

namespace mocap {

double Median(std::vector<double> values) {
  if (values.empty()) return 0;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

double ArWidening(double rho) { return std::sqrt((1 + rho) / (1 - rho)); }

double MeanInterval95(std::span<const double> values, double& rho) {
  const size_t n = values.size();
  rho = 0;
  if (n < 2) return 0;
  double mean = 0;
  for (double v : values) mean += v;
  mean /= static_cast<double>(n);
  double var = 0, cov = 0;
  for (size_t i = 0; i < n; ++i) var += (values[i] - mean) * (values[i] - mean);
  for (size_t i = 1; i < n; ++i) cov += (values[i] - mean) * (values[i - 1] - mean);
  if (var <= 0) return 0;
  rho = std::clamp(cov / var, 0.0, 0.95);
  const double sd = std::sqrt(var / static_cast<double>(n - 1));
  return 1.96 * sd / std::sqrt(static_cast<double>(n)) * ArWidening(rho);
}

}  // namespace mocap
