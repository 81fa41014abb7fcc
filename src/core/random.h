// Reproducible random numbers. std::mt19937_64's output sequence is fixed by the C++ standard, but the
// standard distributions' outputs are not (they differ between library implementations), so uniform and
// normal variates are computed here from the raw 64-bit words: uniform from the top 53 bits, normal by
// Box-Muller. Independent streams (one per purpose) come from mixing a stream id into the seed, so that
// e.g. changing the laser noise does not change the floor plan drawn from the same seed.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

namespace partslam {

class Rng {
 public:
  explicit Rng(std::uint64_t seed, std::uint64_t stream = 0) : engine_(mix(seed ^ mix(stream + 1))) {}

  std::uint64_t bits() { return engine_(); }

  /// Uniform in [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  /// Uniform integer in [0, n), unbiased (rejection of the incomplete top block); 0 when n == 0.
  std::uint64_t index(std::uint64_t n) {
    if (n == 0) return 0;
    const std::uint64_t limit = UINT64_MAX - UINT64_MAX % n;
    std::uint64_t r = engine_();
    while (r >= limit) r = engine_();
    return r % n;
  }

  /// Standard normal variate (Box-Muller; the second value of each pair is kept for the next call).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform();  // (0, 1]: log stays finite
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double a = 2.0 * std::numbers::pi * u2;
    spare_ = r * std::sin(a);
    has_spare_ = true;
    return r * std::cos(a);
  }

  /// Normal variate with the given standard deviation (exactly 0 when sigma == 0, no draw consumed).
  double normal(double sigma) { return sigma == 0.0 ? 0.0 : sigma * normal(); }

 private:
  // SplitMix64 finaliser: spreads nearby seeds / stream ids over the whole 64-bit space.
  static std::uint64_t mix(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace partslam
