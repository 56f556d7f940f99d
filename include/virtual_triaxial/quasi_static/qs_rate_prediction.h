// Prediction of the quasi-static strain rate without a simulation
// (Yousefi 2017, chapter 6.8-6.13, eqs. 80-85).
//
//   Dispersity index (eq. 80): Delta = d_avg / d_min, d_avg the mass-weighted
//   mean nominal diameter, d_min the smallest nominal diameter [-]
//   (computed from a sample by io::dispersity_index; an input here).
//   sigma_bar0 = sigma_c / E, the dimensionless confining stress [-].
//
//   eq. 83 (I_QS = 0.1 %):  eps'_QS = 2.7e-4 e0^-4 sigma_bar0^0.67 Delta^bD
//   eq. 84 (any I_QS):      eps'_QS = 0.27  e0^-4 sigma_bar0^0.67 Delta^bD I_QS
//                            bD = -2 for ND damping, -2.5 for OD (eq. 81)
//   eq. 85 (dimensional):   epsdot_QS = eps'_QS / T0, T0 = d_min sqrt(rho/E)
//     = 0.27 d_min sigma_c^0.67 I_QS / (d_avg^2 rho^0.5 E^0.17 e0^4)   (ND)
//     = 0.27 d_min^1.5 sigma_c^0.67 I_QS / (d_avg^2.5 rho^0.5 E^0.17 e0^4) (OD)
//
// Units: eps' [-], epsdot [1/s], sigma_c and E [Pa], rho [kg/m^3], d [m].
// The project's T0 is L0 sqrt(rho/E) with L0 = 2 x the smallest minor
// semi-axis; for spheres that is d_min of eq. 85 exactly, for spheroids of
// aspect k it is d_min k^(-1/3) (T0 is what the runner uses to turn eps' into
// epsdot, so `dimensional_rate` divides by the runner's T0; `eq85_rate` is
// the printed formula, equal to it for spheres).
//
// Validity (the calibration data, table 39): e0 0.31-0.61, sigma_bar0
// 1e-6 - 8e-5, Delta 1-6.15, 10 000 spheroids of aspect 1.2, mu 0.5,
// nu 0.2, c_t 0.32, drained triaxial shear, xi at the optimum (0.3 % OD,
// 0.5 % ND). Stated accuracy on the leave-out sample: 24 % (ND), 49 % (OD);
// average 24 % / 38 % over all samples (section 6.15). Eq. 84 assumes
// b_I = 1 in eq. 73 (measured 0.47-1.14): conservative for I_QS > 0.1 %, NOT
// for I_QS < 0.1 % (there eps'_QS falls faster than linearly), which is why
// `prediction.extrapolated_threshold` is set for I_QS < 1e-3.
//
// Issue-16 rate strategies call `predict_qs_rate(QsSample, QsDamping, I_QS)`.
#pragma once

#include <string>

namespace vt::quasi_static {

/// The damping model of the run: ND (size-dependent, eq. 63) or OD
/// (conventional, eq. 101). Only the exponent of Delta depends on it.
enum class QsDamping { OD, ND };

/// "OD"/"ND" (case-insensitive); false on anything else.
bool parse_qs_damping(const std::string& text, QsDamping& out);
const char* to_string(QsDamping model);

/// The sample's state at the start of shearing.
struct QsSample {
  double void_ratio = 0.0;          ///< e0 [-]
  double sigma_bar0 = 0.0;          ///< sigma_c / E [-]
  double dispersity_index = 1.0;    ///< Delta (eq. 80) [-], >= 1
};

struct QsRatePrediction {
  double eps_prime_qs = 0.0;          ///< eq. 84 [-]
  double exponent_delta = 0.0;        ///< -2 (ND) or -2.5 (OD)
  double threshold = 1e-3;            ///< I_QS used [-]
  bool inside_calibration = false;    ///< e0, sigma_bar0, Delta within table 39's ranges
  bool extrapolated_threshold = false;///< I_QS < 0.1 %: eq. 84 not conservative
};

/// Eq. 84 (= eq. 83 at I_QS = 1e-3). Throws std::invalid_argument naming
/// the argument (void_ratio, sigma_bar0, dispersity_index, threshold) when it
/// is not finite and > 0 (Delta >= 1).
QsRatePrediction predict_qs_rate(const QsSample& sample, QsDamping model,
                                 double threshold = 1e-3);

/// Eq. 85 as used by the runner: epsdot_QS = eps'_QS / T0 [1/s]; t0 [s] > 0.
double dimensional_rate(double eps_prime, double t0);

/// Eq. 85 literally (d_min, d_avg nominal diameters [m], sigma_c, E [Pa],
/// rho [kg/m^3]). For spheres equal to dimensional_rate(eq. 84, T0).
double eq85_rate(QsDamping model, double d_min, double d_avg, double sigma_c,
                 double density, double young_modulus, double void_ratio,
                 double threshold = 1e-3);

}  // namespace vt::quasi_static
