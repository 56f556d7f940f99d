// Quasi-static rate from a rate sweep (Yousefi 2017, chapter 6.5, eq. 73)
// and from a damping x rate sweep (chapter 7.2.1, eq. 86).
//
//   eq. 73: I_mom = a_I eps'^b_I      (xi fixed at or above its optimum)
//           eps'_QS = (I_QS / a_I)^(1/b_I)
//   eq. 86: I_mom = a_I (xi eps')^b_I  for xi >= xi_opt
//
// I_mom is the mean moment index (eq. 67) from the start of shearing to the
// peak of the mobilized friction angle, as chapter 6 defines it. Two points
// give an exact line (no uncertainty); three or more give R^2 and one
// standard error of ln eps'_QS (eps'_QS x/÷ exp(se) is the 1-sigma band).
// Chapter 6 measured b_I between 0.47 and 1.14; table 42: two points from
// the fastest rates miss the interpolated eps'_QS by 33 % on average, three
// points by 24 %. Extrapolating over more than a decade below the fastest
// rate is where most of that error comes from. Dimensionless throughout.
#pragma once

#include <vector>

#include "virtual_triaxial/quasi_static/power_law_fit.h"

namespace vt::quasi_static {

struct RatePoint {
  double eps_prime = 0.0;   ///< dimensionless strain rate [-]
  double mean_i_mom = 0.0;  ///< mean I_mom from start of shear to the peak [-]
};

struct RateSweepFit {
  PowerLawFit law;               ///< eq. 73 (or eq. 86 with x = xi eps')
  double threshold = 1e-3;       ///< I_QS [-]
  double eps_prime_qs = 0.0;     ///< eq. 73 solved at I_QS [-]
  double se_ln_eps_prime_qs = 0.0;  ///< one standard error of ln eps'_QS (NaN for 2 points)
  double extrapolation_decades = 0.0;  ///< log10(smallest swept eps' / eps'_QS), > 0 when extrapolated
};

/// Eq. 73. Throws std::invalid_argument naming "rates" on bad points and
/// "threshold" on a non-positive I_QS; also when b_I <= 0 (I_mom not rising
/// with the rate: no quasi-static rate can be read off).
RateSweepFit fit_rate_sweep(const std::vector<RatePoint>& points, double threshold = 1e-3);

struct DampingRatePoint {
  double damping_ratio = 0.0;  ///< xi [-]
  double eps_prime = 0.0;      ///< [-]
  double mean_i_mom = 0.0;     ///< [-]
};

/// Eq. 86 over the points with xi >= xi_opt (others are dropped, as the
/// dissertation does). eps_prime_qs is then the (xi eps') product at I_QS:
/// divide by the xi you will run with. Throws like fit_rate_sweep.
RateSweepFit fit_damping_rate_product(const std::vector<DampingRatePoint>& points,
                                      double optimum_ratio, double threshold = 1e-3);

}  // namespace vt::quasi_static
