// The quantiles that summarise a bench's repeated timings (triax_bench's
// turns, host_scaling's rounds).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace vt::bench {

/// The q-quantile of v (0 <= q <= 1), linear between order statistics
/// (q = 0.5: the median; for an even count the mean of the middle two);
/// NaN when v is empty.
inline double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const double x = q * static_cast<double>(v.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(x);
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (x - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

}  // namespace vt::bench
