// input_checks.h -- the argument checks the quasi-static estimators share.
// Each throws std::invalid_argument naming the argument and the reason.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

namespace vt::quasi_static {

/// v must be finite and > 0.
inline void require_positive(double v, const char* name) {
  if (!(std::isfinite(v) && v > 0.0))
    throw std::invalid_argument(std::string(name) + ": must be finite and > 0");
}

/// The dispersity index Delta = d_avg(by mass) / d_min (eq. 80) is >= 1.
inline void require_dispersity_index(double delta) {
  if (!(std::isfinite(delta) && delta >= 1.0))
    throw std::invalid_argument("dispersity_index: must be finite and >= 1");
}

}  // namespace vt::quasi_static
