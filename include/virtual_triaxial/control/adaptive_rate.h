// Adaptive strain rate: hold the moment index at a set fraction of the
// quasi-static threshold (issue 16; I_mom, eqs. 67-68; I_QS, chapter 6).
//
// Each control tick, with I the tick's I_mom and r the current rate [1/s]:
//   smoothed index   S <- S + (I - S) / n_s      (S = I on the first tick;
//                                                 n_s = smoothing_ticks)
//   wanted change    g = (target I_QS / S)^(1 / (kappa n_r))
//   limited change   g <- min(max(g, 1 / (1 + c)), 1 + c),  c = max_change
//   next rate        r <- min(max(r g, eps'_min / T0), eps'_max / T0)
// kappa = d ln I_mom / d ln eps' is the sensitivity of the index to the rate:
// about 0.85 here (I_mom falls 7x per decade of eps' on the shipped dense
// sample, README), so with n_r = 1 the law would close the gap in one tick
// if the index answered at once. It does not: the index lags the rate by the
// time the packing needs to re-balance, and S lags I by about n_s ticks, so
// the law closes the gap over n_r = response_ticks ticks (an integral law in
// log space; n_r of twice the total lag or more keeps it from oscillating),
// and c bounds the change per tick. Rates [1/s]; eps' = eps_dot T0 (eq. 31).
#pragma once

#include "virtual_triaxial/control/adaptive_rate_parameters.h"
#include "virtual_triaxial/control/rate_strategy.h"

namespace vt::control {

class AdaptiveRate : public RateStrategy {
 public:
  /// Throws std::invalid_argument naming the field when `p` is bad.
  explicit AdaptiveRate(const AdaptiveRateParameters& p);
  const char* name() const override { return "adaptive"; }
  void start(double rate0) override;
  double update(const RateInput& in) override;
  double rate() const override { return rate_; }
  /// The rate, the smoothed index and whether it has one (3 numbers).
  std::vector<double> memory() const override { return {rate_, smoothed_, have_index_ ? 1.0 : 0.0}; }
  void restore_memory(const std::vector<double>& m) override;
  /// The smoothed index S [1].
  double smoothed_index() const { return smoothed_; }

 private:
  AdaptiveRateParameters p_;
  double rate_ = 0, smoothed_ = 0;
  bool started_ = false, have_index_ = false;
};

}  // namespace vt::control
