// Time step from the contacts (issue 13): the critical step of the current
// packing, from the stiffest contact of each particle, times a safety factor.
//
// T0 = L0 sqrt(rho/E) (eq. 16, 91-92) is the critical step of a contact as
// stiff as the bulk material; a Hertz contact at overlap delta is far softer
// (K_n ~ E sqrt(R* delta), eq. 116), so at 100 kPa (delta/R ~ 1e-3) the
// contacts allow steps several times T0. For every contact c = (i, j) with
// overlap delta > 0, R* = R_i R_j / (R_i + R_j) (eq. 104):
//   K_n = E/(1 - nu^2) sqrt(R* delta)              normal tangent stiffness (eq. 116) [N/m]
//   K_t = 2 (1 - nu)/(2 - nu) K_n                  tangential stiffness (eq. 114, 117) [N/m]
//   w_n^2 = K_n (1/m_i + 1/m_j)                    normal mode of the pair [1/s^2]
//   w_t^2 = K_t (1/m_i + 1/m_j + l_i^2/I_i + l_j^2/I_j)
//                                                  sliding-rolling mode of the pair:
//                                                  the contact point moves by translation
//                                                  and by rotation (lever l = bounding
//                                                  radius a, I = smallest principal moment)
//   dt_c = 2 / max(w_n, w_t)                       leapfrog stability limit of an
//                                                  undamped oscillator (w dt < 2) [s]
// The packing's critical step is dt_crit = min_c dt_c (each particle's
// stiffest contact), refreshed every check_interval steps and whenever the
// stress has changed by 5 % since (Simulation: ||sum d (x) F||_F; K_n ~
// delta^(1/2) ~ sigma^(1/3), so dt_crit moves by < 1 % in between). Contacts that
// form or close faster than that (a collapsing cloud, a collision) are
// bounded by the impact step dt_imp: the critical step of the stiffest
// contact two of the lightest particles reach in a head-on Hertz impact at
// the largest relative speed u = 2 max|v| + 2 a_max ||L|| of the last step:
// max overlap delta_max = (5 m* u^2 / (4 c_n sqrt(R*)))^(2/5) (Hertz impact,
// m* = m/2, R* = R/2, c_n = 2E/(3(1-nu^2)) of eq. 107), K_n at delta_max in
// the formula above (computed in units of L0, T0 and E, so that the
// dimensionless invariance holds bit for bit). The step is
//   dt = min(s dt_crit, s dt_imp, r_max T0),  s = safety factor, r_max = ceiling in units of T0
// (a packing at rest without contacts takes r_max T0). Two equal spheres (mass m,
// I = 2/5 m R^2): w_t^2 = 7 K_t / m > w_n^2 = 2 K_n / m, so the rolling mode
// sets dt_crit = 2 sqrt(m / (7 K_t)). Several contacts on one particle raise
// its frequency above that of its stiffest contact (up to sqrt(Z) for Z
// equal contacts), which the safety factor covers; the stability monitor
// (stability_monitor.h) still guards every step.
// Dimensionless invariance (section 3.3.2): K/m and l^2/I scale exactly under
// rho x 4, E x 16, L x 2, so dt / T0 depends on the dimensionless state only
// (on sigma_bar = sigma/E for a given packing), bit for bit.
// Spheroids use their nominal radius in R* (as the contact law does, eq. 104)
// and their major semi-axis as lever: an estimate, not a bound.
#pragma once

#include <cstdint>
#include <string>

#include "virtual_triaxial/dem/hertz_mindlin.h"
#include "virtual_triaxial/dem/neighbor_list.h"
#include "virtual_triaxial/dem/particles.h"

namespace vt::dem {

/// What the simulation's time step is proportional to.
enum class TimeStepBasis : std::uint8_t {
  ReferenceTime = 0,  ///< dt = c_t T0 (eq. 132), fixed
  Contacts = 1,       ///< dt = min(s dt_crit, r_max T0), refreshed (this header)
};

/// Parse "reference" / "contacts"; false on anything else.
bool parse_time_step_basis(const std::string& word, TimeStepBasis& out);
const char* to_string(TimeStepBasis b);

struct ContactCriticalStep {
  double dt = 0;               ///< min over contacts of dt_c [s]; +inf without contacts
  double impact = 0;           ///< dt_imp of the last step [s]; +inf at rest
  std::int64_t contacts = 0;   ///< contacts seen
};

class ContactTimeStep {
 public:
  ContactTimeStep() = default;
  /// safety s in (0, 1], ceiling r_max > 0 (units of T0). Throws
  /// std::invalid_argument naming the field otherwise.
  ContactTimeStep(double safety, double max_ratio);

  /// dt_crit of the contacts of the last force evaluation (list pair states).
  static ContactCriticalStep critical_step(const Particles& p, const NeighborList& list, const HertzMindlin& law);
  /// dt_c of one contact (formula above).
  static double pair_critical_step(double k_n, double tangential_ratio, double mass_i, double mass_j,
                                   double lever2_over_inertia_i, double lever2_over_inertia_j);

  /// dt_imp [s] of two particles of mass m, radius r and lever^2/inertia
  /// `rot` (the lightest) at relative speed u [m/s], for the contact law's
  /// c_n and E, time and length scales t0, l0 and density rho (formula above).
  static double impact_critical_step(double u, double m, double r, double rot, const HertzMindlin& law,
                                     double young, double rho, double t0, double l0);
  /// dt = min(s dt_crit, s dt_imp, r_max T0) [s].
  double step(const ContactCriticalStep& c, double impact, double t0) const;
  double safety() const { return safety_; }
  double max_ratio() const { return max_ratio_; }

 private:
  double safety_ = 0.35;
  double max_ratio_ = 2.0;
};

}  // namespace vt::dem
