// Warnings where the dissertation advises against an input (Yousefi 2017):
//
//   * xi = 0 or below the optimum: lower peak strength, worse equilibrium,
//     contractive behaviour, more idle particles (chapter 5.5, section 7.1
//     item 8). Optimum ratios at quasi-static rates: about 0.3 % (OD) and
//     0.5 % (ND) (chapters 5.7 and 6.2); warned below 2/3 of it (table 13's
//     lowest optimum, 0.23 % OD, is 0.77 of 0.3 %).
//   * xi far above the optimum: only xi eps' matters there (eq. 86, chapter
//     5.7), so it acts like a faster test; warned above 3x the optimum.
//   * c_t far from 0.3 for shearing (chapter 3 used 0.32; the project
//     default 0.3): warned outside 0.15-0.45.
//   * a shear rate above the predicted eps'_QS (eq. 84) when a quasi-static
//     result is wanted: peak friction too high (fig. 83).
// Plain numbers in, one-line messages out (each names the protocol field).
#pragma once

#include <string>
#include <vector>

#include "virtual_triaxial/quasi_static/qs_rate_prediction.h"

namespace vt::quasi_static {

/// The optimum damping ratio chapter 6 used: 0.3 % (OD), 0.5 % (ND).
double nominal_optimum_ratio(QsDamping model);

struct QsInputs {
  QsDamping model = QsDamping::OD;
  double damping_ratio = 0.0;        ///< xi [-]
  double time_step_ratio = 0.3;      ///< c_t [-]
  double shear_eps_prime = 0.0;      ///< requested eps' [-] (0: none)
  double predicted_eps_prime_qs = 0.0;  ///< eq. 84 [-] (0: not known)
  bool quasi_static_wanted = true;
};

std::vector<std::string> qs_warnings(const QsInputs& in);

}  // namespace vt::quasi_static
