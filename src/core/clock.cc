#include "core/clock.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/check.h"

namespace mocap {

CounterUnwrapper::CounterUnwrapper(int bits) : range_(bits >= 64 ? 0 : (uint64_t{1} << bits)) {
  MOCAP_CHECK(bits > 0 && bits < 63, "counter width ", bits, " bits is not supported");
}

int64_t CounterUnwrapper::Unwrap(uint64_t raw) {
  MOCAP_CHECK(raw < range_, "counter value ", raw, " exceeds its ", range_, " range");
  if (started_ && raw < last_raw_ && last_raw_ - raw > range_ / 2) ++wraps_;
  if (started_ && raw > last_raw_ && raw - last_raw_ > range_ / 2 && wraps_ > 0) {
    // A late sample from before the last wrap: attribute it to the previous lap.
    return static_cast<int64_t>(raw + range_ * static_cast<uint64_t>(wraps_ - 1));
  }
  started_ = true;
  last_raw_ = raw;
  return static_cast<int64_t>(raw + range_ * static_cast<uint64_t>(wraps_));
}

void ClockFitOptions::check() const {
  if (!(tukey_c > 0)) throw InputError("ClockFitOptions", "tukey_c must be positive");
  if (max_iterations < 1) throw InputError("ClockFitOptions", "max_iterations must be >= 1");
  if (min_samples < 2) throw InputError("ClockFitOptions", "min_samples must be >= 2");
}

int64_t ClockFit::HostNs(int64_t ticks) const {
  return static_cast<int64_t>(std::llround(offset_ns + ns_per_tick * static_cast<double>(ticks - ticks_origin)));
}

namespace {

struct Line {
  double a, b;  // y = a + b x
};

Line WeightedLine(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& w) {
  double sw = 0, sx = 0, sy = 0;
  for (size_t i = 0; i < x.size(); ++i) sw += w[i], sx += w[i] * x[i], sy += w[i] * y[i];
  const double mx = sx / sw, my = sy / sw;
  double sxx = 0, sxy = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sxx += w[i] * (x[i] - mx) * (x[i] - mx);
    sxy += w[i] * (x[i] - mx) * (y[i] - my);
  }
  const double b = sxx > 0 ? sxy / sxx : 0.0;
  return {my - b * mx, b};
}

double MedianAbs(std::vector<double> v) {
  for (double& e : v) e = std::abs(e);
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

ClockFit FitClock(std::span<const int64_t> device_ticks, std::span<const int64_t> host_ns,
                  const ClockFitOptions& options) {
  options.check();
  if (device_ticks.size() != host_ns.size())
    throw InputError("FitClock", Str(device_ticks.size(), " device stamps but ", host_ns.size(), " host stamps"));
  if (static_cast<int>(device_ticks.size()) < options.min_samples)
    throw InputError("FitClock", Str("needs at least ", options.min_samples, " samples, got ", device_ticks.size()));
  ClockFit fit;
  fit.samples = static_cast<int>(device_ticks.size());
  fit.ticks_origin = device_ticks.front();
  const int64_t host_origin = host_ns.front();
  std::vector<double> x(device_ticks.size()), y(device_ticks.size()), w(device_ticks.size(), 1.0);
  for (size_t i = 0; i < x.size(); ++i) {
    x[i] = static_cast<double>(device_ticks[i] - fit.ticks_origin);
    y[i] = static_cast<double>(host_ns[i] - host_origin);
  }
  if (std::all_of(x.begin(), x.end(), [](double v) { return v == 0.0; }))
    throw InputError("FitClock", "device stamps do not change");
  Line line = WeightedLine(x, y, w);
  std::vector<double> r(x.size());
  for (fit.iterations = 1; fit.iterations <= options.max_iterations; ++fit.iterations) {
    for (size_t i = 0; i < x.size(); ++i) r[i] = y[i] - (line.a + line.b * x[i]);
    const double scale = std::max(1.4826 * MedianAbs(r), 1.0);  // 1 ns floor: exact data
    for (size_t i = 0; i < x.size(); ++i) {
      const double u = r[i] / (options.tukey_c * scale);
      w[i] = std::abs(u) < 1.0 ? (1 - u * u) * (1 - u * u) : 0.0;
    }
    const Line next = WeightedLine(x, y, w);
    const bool converged = std::abs(next.a - line.a) < 1e-3 && std::abs(next.b - line.b) < 1e-12;
    line = next;
    if (converged) break;
  }
  fit.iterations = std::min(fit.iterations, options.max_iterations);
  fit.offset_ns = line.a + static_cast<double>(host_origin);
  fit.ns_per_tick = line.b;
  double sum_sq = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    const double res = y[i] - (line.a + line.b * x[i]);
    fit.residual_max_ns = std::max(fit.residual_max_ns, std::abs(res));
    if (w[i] > 0) sum_sq += res * res, ++fit.inliers;
  }
  fit.residual_rms_ns = fit.inliers > 0 ? std::sqrt(sum_sq / fit.inliers) : 0.0;
  return fit;
}

}  // namespace mocap
