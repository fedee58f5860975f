#pragma once
/// SplitMix64: a small seeded generator whose draws are the same on every platform and standard
/// library (std:: distributions are implementation-defined), for reproducible randomness.

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "glassmap/core/angles.hpp"

namespace glassmap {

/// SplitMix64's step and output function (Steele, Lea and Flood 2014) on one value: independent,
/// reproducible seeds for separate random streams from one seed and a stream's index.
inline std::uint64_t splitMix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

class SplitMix {
 public:
  explicit SplitMix(std::uint64_t seed) : s_(seed) {}
  std::uint64_t next() {
    const std::uint64_t z = splitMix64(s_);
    s_ += 0x9e3779b97f4a7c15ULL;
    return z;
  }
  /// Uniform in [0, 1), from the top 53 bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Standard normal (Box–Muller, one of the pair; two draws).
  double normal() {
    const double u1 = std::max(uniform(), 1e-300), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
  }

 private:
  std::uint64_t s_;
};

}  // namespace glassmap
