// Settings of the adaptive strain-rate law (adaptive_rate.h), separate so
// that rate_strategy.h's RateSpec can hold them. Dimensionless rates are
// eps' = eps_dot T0 (eq. 31); t0 [s].
#pragma once

#include <string>

namespace vt::control {

struct AdaptiveRateParameters {
  double target = 0.7;            ///< S is held at target * I_QS, in (0, 1]
  double min_dimensionless = 1e-9;  ///< eps'_min, > 0
  double max_dimensionless = 1e-4;  ///< eps'_max, >= eps'_min
  double max_change = 0.02;       ///< c: largest relative rate change per tick, in (0, 1]
  double smoothing_ticks = 20;    ///< n_s >= 1
  double response_ticks = 60;     ///< n_r >= 1
  double sensitivity = 0.85;      ///< kappa > 0
  double t0 = 0;                  ///< T0 of the sample [s], > 0
};

/// "" or "<field>: <reason>".
std::string validate(const AdaptiveRateParameters& p);

}  // namespace vt::control
