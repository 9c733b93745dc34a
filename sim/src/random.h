// Private: a small, platform-independent random source for the simulator. The standard library's
// distributions differ between implementations, and std::normal_distribution is slow enough to
// matter at 290,000 LiDAR returns per simulated second; these are fixed formulas.
#pragma once

#include <cmath>
#include <cstdint>

#include "ovpc/core/internal/hash.h"

namespace ovpc::sim {

/// splitmix64 (ovpc/core/internal/hash.h).
using ovpc::internal::Mix;
using ovpc::internal::ToUnitInterval;

/// Combines a running hash with a value; order matters.
inline std::uint64_t HashCombine(std::uint64_t h, std::uint64_t value) {
  return Mix(h ^ Mix(value + 0x632be59bd9b4e019ULL));
}


/// xoshiro256++ seeded through splitmix64, with uniform and Gaussian draws (Marsaglia's polar
/// method, second value kept).
class Rng {
 public:
  explicit Rng(std::uint64_t seed = 1) { Seed(seed); }

  void Seed(std::uint64_t seed) {
    std::uint64_t x = seed;
    for (std::uint64_t& word : s_) {
      x += ovpc::internal::kGoldenGamma;
      word = Mix(x);
    }
    has_spare_ = false;
  }

  std::uint64_t Next() {
    const std::uint64_t result = Rotl(s_[0] + s_[3], 23) + s_[0];
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = Rotl(s_[3], 45);
    return result;
  }

  /// Uniform in [0, 1).
  double Uniform() { return ToUnitInterval(Next()); }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }

  /// Standard normal.
  double Gaussian() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u = 0.0;
    double v = 0.0;
    double s = 0.0;
    do {
      u = 2.0 * Uniform() - 1.0;
      v = 2.0 * Uniform() - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double scale = std::sqrt(-2.0 * std::log(s) / s);
    spare_ = v * scale;
    has_spare_ = true;
    return u * scale;
  }

 private:
  static std::uint64_t Rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

  std::uint64_t s_[4] = {};
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace ovpc::sim
