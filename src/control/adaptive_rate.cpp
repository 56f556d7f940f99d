#include "virtual_triaxial/control/adaptive_rate.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vt::control {

std::string validate(const AdaptiveRateParameters& p) {
  if (!(p.target > 0.0 && p.target <= 1.0)) return "target: must be in (0, 1]";
  if (!(std::isfinite(p.min_dimensionless) && p.min_dimensionless > 0.0)) return "min: must be finite and > 0";
  if (!(std::isfinite(p.max_dimensionless) && p.max_dimensionless >= p.min_dimensionless))
    return "max: must be finite and >= min";
  if (!(p.max_change > 0.0 && p.max_change <= 1.0)) return "max_change: must be in (0, 1]";
  if (!(std::isfinite(p.smoothing_ticks) && p.smoothing_ticks >= 1.0)) return "smoothing_ticks: must be >= 1";
  if (!(std::isfinite(p.response_ticks) && p.response_ticks >= 1.0)) return "response_ticks: must be >= 1";
  if (!(std::isfinite(p.sensitivity) && p.sensitivity > 0.0)) return "sensitivity: must be finite and > 0";
  if (!(std::isfinite(p.t0) && p.t0 > 0.0)) return "t0: must be finite and > 0";
  return {};
}

AdaptiveRate::AdaptiveRate(const AdaptiveRateParameters& p) : p_(p) {
  const std::string bad = validate(p);
  if (!bad.empty()) throw std::invalid_argument(bad);
}

void AdaptiveRate::restore_memory(const std::vector<double>& m) {
  if (m.size() != 3) throw std::invalid_argument("rate memory: 'adaptive' keeps 3 numbers");
  rate_ = m[0];
  smoothed_ = m[1];
  have_index_ = m[2] != 0.0;
}

void AdaptiveRate::start(double rate0) {
  if (!(std::isfinite(rate0) && rate0 > 0.0)) throw std::invalid_argument("rate0: must be finite and > 0");
  rate_ = std::min(std::max(rate0, p_.min_dimensionless / p_.t0), p_.max_dimensionless / p_.t0);
  started_ = true;
  have_index_ = false;
}

double AdaptiveRate::update(const RateInput& in) {
  if (!started_) throw std::logic_error("AdaptiveRate::update before start");
  if (!(std::isfinite(in.moment_index) && in.moment_index >= 0.0))
    throw std::invalid_argument("moment_index: must be finite and >= 0");
  if (!(in.quasi_static_threshold > 0.0)) throw std::invalid_argument("quasi_static_threshold: must be > 0");
  smoothed_ = have_index_ ? smoothed_ + (in.moment_index - smoothed_) / p_.smoothing_ticks : in.moment_index;
  have_index_ = true;
  const double hi = 1.0 + p_.max_change, lo = 1.0 / hi;
  // S = 0 (no contacts yet): the largest allowed rise
  const double want = smoothed_ > 0.0 ? std::pow(p_.target * in.quasi_static_threshold / smoothed_,
                                                         1.0 / (p_.sensitivity * p_.response_ticks))
                                      : hi;
  const double g = std::min(std::max(want, lo), hi);
  rate_ = std::min(std::max(rate_ * g, p_.min_dimensionless / p_.t0), p_.max_dimensionless / p_.t0);
  return rate_;
}

}  // namespace vt::control
