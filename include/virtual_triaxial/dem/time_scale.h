// Dimensionless time scheme (chapter 3.2, appendix 1).
//
//   L0 = 2 x smallest minor semi-axis (= 2 R_min for spheres)   (eq. 15)
//   T0 = L0 sqrt(rho / E) = critical time step Dt_c             (eq. 16, 91-92)
//   Dt = c_t T0                                                  (eq. 132)
//   dimensionless strain rate eps' = eps_dot T0                  (eq. 31)
//   dimensionless stress sigma_bar = sigma / E                   (eq. 41)
//   dimensionless time tau = t / T0                              (eq. 17)
#pragma once

namespace vt::dem {

struct TimeScale {
  double l0 = 0.0;  ///< characteristic length [m]
  double t0 = 0.0;  ///< characteristic time = critical time step [s]
  double ct = 0.0;  ///< time-step ratio [-]
  double dt = 0.0;  ///< time step [s]

  static TimeScale from(double min_minor_semi_axis, double density, double young, double ct);
  double strain_rate_from_dimensionless(double eps_prime) const { return eps_prime / t0; }
  double dimensionless_strain_rate(double eps_dot) const { return eps_dot * t0; }
};

}  // namespace vt::dem
