// Least-squares power law y = a x^b fitted as the straight line
// ln y = ln a + b ln x (the log-log lines of figs. 35, 47-50, 70-74 of
// Yousefi 2017; chapter 6.5's two- and three-point approximations of
// table 42 are reproduced by exactly this fit).
//
// R^2 is that of the fitted line in log-log space. Standard errors are the
// ordinary least-squares ones of the line (need >= 3 points; with 2 points
// the line is exact and the errors are NaN). Dimensionless; x, y > 0.
#pragma once

#include <vector>

namespace vt::quasi_static {

struct PowerLawFit {
  double a = 0.0;          ///< coefficient
  double b = 0.0;          ///< exponent
  double r_squared = 0.0;  ///< in log-log space (NaN with 2 points: exact)
  int points = 0;
  double mean_ln_x = 0.0;  ///< centre of the fitted line
  double mean_ln_y = 0.0;  ///< ln y at the centre (uncorrelated with b)
  double se_mean_ln_y = 0.0;  ///< standard error of mean_ln_y (NaN for 2 points)
  double se_b = 0.0;          ///< standard error of b (NaN for 2 points)

  double operator()(double x) const;
  /// x at which the line reaches y, with one standard error of ln x
  /// (delta method; NaN for 2 points).
  double solve_x(double y) const;
  double se_ln_solve_x(double y) const;
};

/// Throws std::invalid_argument("<name>: ...") for fewer than 2 points,
/// unequal sizes, non-positive or non-finite values, or all x equal.
PowerLawFit fit_power_law(const std::vector<double>& x, const std::vector<double>& y,
                          const char* name = "points");

}  // namespace vt::quasi_static
