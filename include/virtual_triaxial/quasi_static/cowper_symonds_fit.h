// Quasi-static peak friction from the rate dependence of the peak itself
// (Yousefi 2017, eq. 75; chapter 6.16 method (a); Cowper-Symonds form, eq. 76):
//
//   tan phi_peak = tan phi_0 + a_phi eps'^b_phi      tan phi_QS = tan phi_0
//
// Three parameters: for a fixed b_phi the model is linear in (tan phi_0,
// a_phi), solved by least squares; b_phi minimises the residual sum of
// squares over (0.02, 3] (a log-spaced scan then golden-section refinement;
// deterministic). With three runs the fit is exact when a solution exists
// (the dissertation solved the same 3x3 system by Newton-Raphson).
// Table 47(a): 5.1 % average error in tan phi_QS, against 1.8 % for eq. 74
// from the same runs: prefer eq. 74. Dimensionless rates; angles in degrees.
#pragma once

#include <vector>

namespace vt::quasi_static {

struct RateFrictionPoint {
  double eps_prime = 0.0;     ///< [-]
  double phi_peak_deg = 0.0;  ///< [deg]
};

struct CowperSymondsFit {
  double tan_phi_qs = 0.0;   ///< tan phi_0 [-]
  double phi_qs_deg = 0.0;   ///< [deg]
  double a_phi = 0.0;        ///< [-]
  double b_phi = 0.0;        ///< [-]
  double rss = 0.0;          ///< residual sum of squares of tan phi [-]
  bool b_at_bound = false;   ///< the best b_phi is at an end of the search interval
};

/// Throws std::invalid_argument("rates...") for fewer than 3 runs, repeated
/// or non-positive rates, or angles outside (0, 90) deg.
CowperSymondsFit fit_cowper_symonds(const std::vector<RateFrictionPoint>& points);

}  // namespace vt::quasi_static
