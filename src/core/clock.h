#pragma once
// Device clocks onto the host clock (DESIGN.md "Time"). Every sample keeps its device timestamp and its
// host monotonic receive time; the device counter is unwrapped, then mapped onto host time by a robust
// linear fit whose residuals are reported (and written into the session manifest).
#include <cstdint>
#include <span>
#include <string>

namespace mocap {

/// Unwraps a free-running counter of `bits` bits (Kinect1: 32-bit at 60 MHz, wrapping every 71.6 s)
/// into a monotonic 64-bit count. A step backwards of more than half the range counts as a wrap; a
/// smaller step backwards is kept as is (reordered packet), not treated as a wrap.
class CounterUnwrapper {
 public:
  explicit CounterUnwrapper(int bits);
  int64_t Unwrap(uint64_t raw);
  int wraps() const { return wraps_; }

 private:
  uint64_t range_;
  bool started_ = false;
  uint64_t last_raw_ = 0;
  int wraps_ = 0;
};

struct ClockFitOptions {
  /// Residuals beyond this many robust standard deviations get zero weight (Tukey biweight).
  double tukey_c = 4.685;
  int max_iterations = 20;
  /// Needs at least this many samples to fit.
  int min_samples = 2;
  void check() const;
};

/// host_ns = offset_ns + ns_per_tick * (ticks - ticks_origin). Centring on ticks_origin keeps the fit
/// well-conditioned for counters in the 1e12 range.
struct ClockFit {
  int64_t ticks_origin = 0;
  double offset_ns = 0.0;
  double ns_per_tick = 1.0;
  double residual_rms_ns = 0.0;  ///< over the inliers
  double residual_max_ns = 0.0;  ///< over all samples
  int samples = 0;
  int inliers = 0;
  int iterations = 0;

  int64_t HostNs(int64_t ticks) const;
};

/// Robust (IRLS, Tukey biweight on the MAD scale) straight-line fit of host receive times against
/// device ticks. Throws InputError when fewer than min_samples pairs are given or the sizes differ, or
/// the ticks do not vary.
ClockFit FitClock(std::span<const int64_t> device_ticks, std::span<const int64_t> host_ns,
                  const ClockFitOptions& options = {});

}  // namespace mocap
