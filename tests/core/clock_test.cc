#include "core/clock.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "core/check.h"

namespace mocap {
namespace {

TEST(CounterUnwrapper, UnwrapsKinect1ThirtyTwoBitCounter) {
  CounterUnwrapper unwrap(32);
  const uint64_t range = uint64_t{1} << 32;
  EXPECT_EQ(unwrap.Unwrap(range - 2'000'000), static_cast<int64_t>(range - 2'000'000));
  EXPECT_EQ(unwrap.Unwrap(1'000'000), static_cast<int64_t>(range + 1'000'000));  // wrapped
  EXPECT_EQ(unwrap.wraps(), 1);
  // A slightly late sample from before the wrap stays in the previous lap.
  EXPECT_EQ(unwrap.Unwrap(range - 1'000'000), static_cast<int64_t>(range - 1'000'000));
  EXPECT_EQ(unwrap.Unwrap(3'000'000), static_cast<int64_t>(range + 3'000'000));
  EXPECT_EQ(unwrap.wraps(), 1);
}

TEST(ClockFit, RecoversRateAndOffsetDespiteOutliers) {
  // A 60 MHz device counter, host receive time = 1e9 + ticks * 16.6667 ns + jitter, 5% late deliveries.
  std::mt19937 rng(7);
  std::normal_distribution<double> jitter(0.0, 50'000.0);  // 50 us
  std::vector<int64_t> ticks, host;
  const double ns_per_tick = 1e9 / 60e6;
  for (int i = 0; i < 600; ++i) {
    const int64_t t = 4'000'000'000LL + i * 2'000'000LL;  // 30 Hz
    double h = 1e12 + static_cast<double>(t) * ns_per_tick + jitter(rng);
    if (i % 20 == 7) h += 30e6;  // a 30 ms scheduling hiccup
    ticks.push_back(t);
    host.push_back(static_cast<int64_t>(h));
  }
  const ClockFit fit = FitClock(ticks, host);
  EXPECT_NEAR(fit.ns_per_tick, ns_per_tick, 1e-5);
  EXPECT_LT(std::abs(static_cast<double>(fit.HostNs(ticks[100])) - (1e12 + ticks[100] * ns_per_tick)), 20'000.0);
  EXPECT_NEAR(fit.residual_rms_ns, 50'000.0, 10'000.0);
  EXPECT_GT(fit.residual_max_ns, 29e6);
  EXPECT_EQ(fit.samples, 600);
  EXPECT_EQ(fit.inliers, 570);
}

TEST(ClockFit, RejectsBadInput) {
  const std::vector<int64_t> one = {1};
  EXPECT_THROW(FitClock(one, one), InputError);
  const std::vector<int64_t> same = {5, 5, 5}, host = {1, 2, 3};
  EXPECT_THROW(FitClock(same, host), InputError);
  const std::vector<int64_t> two = {1, 2};
  EXPECT_THROW(FitClock(two, host), InputError);
}

}  // namespace
}  // namespace mocap
