// Viscous contact damping from a coefficient of restitution e, in the Tsuji
// form (Tsuji, Tanaka & Ishida 1992; the nonlinear dashpot that LAMMPS
// `damping tsuji` and LIGGGHTS' Hertz models put beside a Hertz spring).
//
// A dashpot acts in every contact beside the Hertz-Mindlin springs
// (hertz_mindlin.h), on the relative velocity of the contact point
// v_c = v_n n + v_t (v_n = v_c . n > 0 when the pair separates):
//     F_n,d = -eta_n v_n n,   eta_n = a sqrt(m* K_n)          [N s/m]
//     F_t,d = -eta_t v_t,     eta_t = a sqrt(m* K_t)          [N s/m]
// with m* = m_i m_j / (m_i + m_j) [kg] and the tangent stiffnesses of the
// springs, K_n = dF_n/ddelta = 1.5 k sqrt(delta) (eq. 116; k = 2E/(3(1-nu^2))
// sqrt(R*), F_n = k delta^1.5, eq. 107) and K_t = 2(1-nu)/(2-nu) K_n
// (eq. 114). Both grow as delta^(1/4): the Tsuji form. The tangential
// dashpot uses the same a, so the tangential spring-dashpot has the same
// damping as the normal one (as LIGGGHTS' Hertz model does); it acts while
// the contact sticks and is off while it slides (the Coulomb cap of eq. 113
// bounds the spring alone). The normal force may turn attractive at the end
// of a collision (LAMMPS' and LIGGGHTS' default; no `limitForce`).
//
// How a follows from e (derivation). A head-on collision with approach speed
// v0: m* delta'' = -k delta^1.5 - a sqrt(1.5 m* k) delta^(1/4) delta'. With
// delta = s x, t = tau u, s = (m* v0^2 / k)^(2/5), u = s / v0, it becomes
//     x'' = -x^1.5 - beta x^(1/4) x',  x(0) = 0, x'(0) = 1,  beta = a sqrt(1.5),
// free of v0, masses, radii and moduli: e = -x'(end) at the return to x = 0
// depends on a alone, so one a gives the same e at every impact speed (the
// point of the Tsuji form). e(beta) has no closed form: restitution_of()
// integrates the equation (RK4, 4000 steps per unit tau: halving the step
// changes e by less than 1e-6) and coefficient_for() inverts it by
// bisection, once per setting (tens of milliseconds).
// Examples: e = 0.9 -> a = 0.061, e = 0.5 -> a = 0.39, e = 0.2 -> a = 0.83.
// (LAMMPS' fitted polynomial a(e) belongs to its own stiffness convention;
// here a is derived for the one above.)
//
// Units: e [1], a [1], eta [N s/m].
#pragma once

#include <cmath>
#include <string>

#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

class ViscousContactDamping {
 public:
  ViscousContactDamping() = default;
  /// e in (0, 1]; throws std::invalid_argument otherwise. e = 1: no damping.
  explicit ViscousContactDamping(double restitution);

  double restitution() const { return restitution_; }
  /// a of the dashpots (see above) [1].
  double coefficient() const { return a_; }

  /// eta = a sqrt(m* K) [N s/m] for effective mass m* [kg] and tangent stiffness K [N/m].
  double eta(double m_eff, double stiffness) const { return a_ * std::sqrt(m_eff * stiffness); }

  /// e of a head-on Hertz collision for the dimensionless damping beta = a sqrt(1.5).
  static double restitution_of(double beta);
  /// a such that restitution_of(a sqrt(1.5)) = e (e in (0, 1]).
  static double coefficient_for(double restitution);

 private:
  double restitution_ = 1.0;
  double a_ = 0.0;
};

}  // namespace vt::dem
