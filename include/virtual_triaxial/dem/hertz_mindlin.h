// Simplified Hertz-Mindlin contact law (appendix 3 of the dissertation).
//
// Normal force, Hertz (eq. 107), overlap delta [m], R_i, R_j [m]:
//     |F_n| = 2E / (3 (1 - nu^2)) * sqrt(R* delta^3),   R* = R_i R_j / (R_i + R_j)  (eq. 104)
// Normal stiffness (eq. 115-116):
//     K_n = d|F_n|/d delta = E / (1 - nu^2) * sqrt(R* delta)          [N/m]
// Tangential stiffness (eq. 114, 117):
//     K_t = 2 (1 - nu) / (2 - nu) * K_n                               [N/m]
// Tangential force, incremental (eq. 113/118): the stored tangential force is
// first rotated into the current tangent plane (projected, magnitude kept),
// then F_t <- F_t - K_t * d_t, with d_t the tangential relative displacement
// increment of the contact over the step; then the Coulomb cap
// |F_t| <= mu |F_n| (eq. 113) is applied.
//
// Normal elastic energy (exact for Hertz): U_n = 2/5 |F_n| delta [J].
// Tangential elastic energy: U_t = |F_t|^2 / (2 K_t) [J].
// Friction dissipation on a slipping step: mu|F_n| * (|F_trial| - mu|F_n|) / K_t.
//
// Every operation scales exactly under power-of-two changes of E and length
// (the square root only ever sees R* delta, a product of two lengths).
// For spheroids R_i is the particle's average radius (eq. 104).
#pragma once

#include "virtual_triaxial/dem/material.h"
#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

/// Result of one contact evaluation. Forces act on particle j (the one the
/// normal points to); the force on i is the negative.
struct ContactResult {
  Vec3 force_on_j;          ///< [N]
  double normal_force = 0;  ///< |F_n| [N]
  double elastic_energy = 0;      ///< U_n + U_t [J]
  double friction_dissipation = 0;  ///< energy dissipated by sliding this step [J]
  bool sliding = false;
};

class HertzMindlin {
 public:
  HertzMindlin() = default;
  explicit HertzMindlin(const Material& m) { set_material(m); }

  void set_material(const Material& m) {
    normal_coef_ = 2.0 * m.young / (3.0 * (1.0 - m.poisson * m.poisson));
    tangential_ratio_ = 2.0 * (1.0 - m.poisson) / (2.0 - m.poisson);
    friction_ = m.friction;
  }
  void set_friction(double mu) { friction_ = mu; }
  double friction() const { return friction_; }

  /// 2E / (3 (1 - nu^2)) [Pa], the prefactor of eq. 107.
  double normal_coefficient() const { return normal_coef_; }
  double tangential_ratio() const { return tangential_ratio_; }

  /// |F_n| for overlap delta and effective radius r_eff (eq. 107).
  double normal_force(double delta, double r_eff) const {
    return normal_coef_ * std::sqrt(r_eff * delta) * delta;
  }
  /// K_n for overlap delta (eq. 116).
  double normal_stiffness(double delta, double r_eff) const {
    return 1.5 * normal_coef_ * std::sqrt(r_eff * delta);
  }

  /// Evaluate one contact.
  ///   n        unit normal from i to j
  ///   delta    overlap > 0 [m]
  ///   r_eff    R* [m]
  ///   dv_t_dt  tangential relative displacement increment of j w.r.t. i over
  ///            the step [m] (already projected into the tangent plane)
  ///   spring   stored tangential force on j [N], updated in place
  ContactResult evaluate(const Vec3& n, double delta, double r_eff, const Vec3& d_t,
                         Vec3& spring) const {
    ContactResult r;
    const double root = std::sqrt(r_eff * delta);
    const double fn = normal_coef_ * root * delta;
    const double kt = tangential_ratio_ * 1.5 * normal_coef_ * root;

    // Rotate the stored force into the current tangent plane, keeping its size.
    Vec3 ft = spring;
    const double old2 = norm2(ft);
    if (old2 > 0.0) {
      ft -= dot(ft, n) * n;
      const double new2 = norm2(ft);
      if (new2 > 0.0) ft *= std::sqrt(old2 / new2);
    }
    ft -= kt * d_t;

    const double cap = friction_ * fn;
    const double ft2 = norm2(ft);
    if (ft2 > cap * cap) {
      const double mag = std::sqrt(ft2);
      r.sliding = true;
      // delta = 0 (possible by rounding at first touch): kt = cap = 0 and
      // the limit of cap (mag - cap) / kt as delta -> 0 is 0 (not 0/0).
      r.friction_dissipation = kt > 0.0 ? cap * (mag - cap) / kt : 0.0;
      ft *= cap / mag;
    }
    spring = ft;
    r.normal_force = fn;
    r.force_on_j = fn * n + ft;
    r.elastic_energy = 0.4 * fn * delta + (kt > 0.0 ? 0.5 * norm2(ft) / kt : 0.0);
    return r;
  }

 private:
  double normal_coef_ = 0.0;
  double tangential_ratio_ = 0.0;
  double friction_ = 0.0;
};

}  // namespace vt::dem
