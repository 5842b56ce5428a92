#pragma once
// A seeded random source whose sequence is the same on every platform: std::mt19937_64 is specified
// bit-exactly by the standard, the std:: distributions are not, so uniform and normal draws are built
// here (normal by Box-Muller). Every simulated artefact draws from one of these, seeded from the
// scenario seed, so a simulation is reproducible byte for byte.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

namespace mocap::sim {

class Rng {
 public:
  explicit Rng(uint64_t seed) : engine_(seed) {}
  /// Derives an independent stream for a sub-task (a frame, a body) from a base seed.
  static Rng Derive(uint64_t seed, uint64_t stream) { return Rng(Mix(seed ^ Mix(stream + 0x9e3779b97f4a7c15ULL))); }

  /// Uniform in [0, 1).
  double Uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  bool Bernoulli(double p) { return Uniform() < p; }
  /// Standard normal.
  double Normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = Uniform();
    while (u1 <= 0.0) u1 = Uniform();
    const double u2 = Uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * std::numbers::pi * u2);
    has_spare_ = true;
    return r * std::cos(2.0 * std::numbers::pi * u2);
  }
  double Normal(double sigma) { return sigma * Normal(); }

 private:
  /// SplitMix64 finaliser: spreads nearby seeds over the whole state space.
  static uint64_t Mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace mocap::sim
