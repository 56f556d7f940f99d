// Deterministic random numbers, identical on every platform and compiler:
// std::mt19937_64 is fully specified by the standard, but the standard
// distributions are not, so the conversions to doubles are written here.
#pragma once

#include <cstdint>
#include <random>

namespace vt::dem {

class RandomStream {
 public:
  explicit RandomStream(std::uint64_t seed) : engine_(seed) {}
  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

 private:
  std::mt19937_64 engine_;
};

}  // namespace vt::dem
