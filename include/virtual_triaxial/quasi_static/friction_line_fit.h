// Quasi-static peak friction from fast runs: the linear law between the peak
// friction coefficient and the moment index (Yousefi 2017, eq. 74 = eq. 69 =
// eq. 87; da Cruz et al. 2005 found the same with the inertial number):
//
//   tan phi_peak = tan phi_QS + k I_mom        (for xi >= xi_opt)
//
// Least-squares line through (mean I_mom to the peak, tan phi_peak); its
// intercept at I_mom = 0 is the quasi-static peak friction coefficient.
// Used two ways:
//   * rate sweep (chapter 6.16, method (b)): runs at several fast rates, one
//     xi: table 47(b) reports 1.8 % average error in tan phi_QS from the
//     three rates 1e-5, 5e-6, 2e-6;
//   * damping sweep (chapter 5.5-5.6): runs at one fast rate with several
//     xi; only the points with xi >= xi_opt lie on the line (below the
//     optimum phi_peak is too LOW, fig. 51-54), see
//     `fit_friction_line_above_optimum`. Tables 15 and 30.
// Units: angles in degrees at the interface ([deg]), I_mom and k [-].
// Validity: needs >= 2 points with distinct I_mom; a standard error of the
// intercept needs >= 3. k < 0 (phi falls as I_mom rises) is not physical
// and is flagged.
#pragma once

#include <vector>

namespace vt::quasi_static {

struct FrictionPoint {
  double mean_i_mom = 0.0;    ///< [-]
  double phi_peak_deg = 0.0;  ///< [deg]
  double damping_ratio = 0.0; ///< xi [-] (used by the damping-sweep form only)
};

struct FrictionLineFit {
  double tan_phi_qs = 0.0;     ///< intercept [-]
  double phi_qs_deg = 0.0;     ///< atan(intercept) [deg]
  double slope = 0.0;          ///< k [-]
  double r_squared = 0.0;      ///< NaN for 2 points
  double se_phi_qs_deg = 0.0;  ///< one standard error of phi_QS [deg] (NaN for 2 points)
  int points = 0;
  bool slope_positive = true;  ///< false: phi falls with I_mom, the law does not hold
};

/// Eq. 74 through every point. Throws std::invalid_argument naming `name`
/// (fewer than 2 points, non-finite values, all I_mom equal).
FrictionLineFit fit_friction_line(const std::vector<FrictionPoint>& points,
                                  const char* name = "points");

/// Chapter 5's damping-based estimator: eq. 74 through the points whose
/// damping ratio is >= optimum_ratio.
FrictionLineFit fit_friction_line_above_optimum(const std::vector<FrictionPoint>& points,
                                                double optimum_ratio);

}  // namespace vt::quasi_static
