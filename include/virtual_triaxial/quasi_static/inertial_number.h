// The inertial-number form of the quasi-static rate (da Cruz et al. 2005, as
// used in Yousefi 2017, chapter 6.1-6.2 and 6.15).
//
//   eq. 70: I = epsdot d_avg sqrt(rho / sigma_m)            [-]
//   eq. 72: eps' = I sqrt(sigma_bar0) / Delta   (eq. 70 in the dimensionless
//           scheme: epsdot = eps'/T0, T0 = d_min sqrt(rho/E), sigma_m =
//           sigma_bar0 E, Delta = d_avg/d_min)
//
// Units: epsdot [1/s], d_avg [m], rho [kg/m^3], sigma_m [Pa].
// The threshold I that makes eq. 72 best fit the simulated eps'_QS of
// table 40/41 (section 6.15): 5.8e-4 for ND, 3.7e-4 for OD; the literature
// values are 2e-4 (Macaro and Utili 2012, peak) and 2.5e-3 (Perez et al.
// 2016, critical state only). Eq. 72 ignores e0; chapter 6 finds its average
// error 98 % (ND) / 202 % (OD) against 24 % / 38 % for eq. 84: it is shown
// beside eq. 84, not instead of it.
#pragma once

#include "virtual_triaxial/quasi_static/qs_rate_prediction.h"

namespace vt::quasi_static {

/// Section 6.15's fitted inertial-number threshold for a damping model.
double fitted_inertial_threshold(QsDamping model);

/// Eq. 70. Throws std::invalid_argument naming a non-positive argument.
double inertial_number(double strain_rate, double d_avg, double density, double mean_stress);

/// Eq. 72: the dimensionless rate at which the inertial number equals
/// `inertial_threshold` for a sample (e0 is not used).
double eq72_rate(const QsSample& sample, double inertial_threshold);

}  // namespace vt::quasi_static
