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
  ///   delta    overlap >= 0 [m] (0: no force, and the spring is dropped)
  ///   r_eff    R* [m]
  ///   dv_t_dt  tangential relative displacement increment of j w.r.t. i over
  ///            the step [m] (already projected into the tangent plane)
  ///   spring   stored tangential force on j [N], updated in place
  ContactResult evaluate(const Vec3& n, double delta, double r_eff, const Vec3& d_t,
                         Vec3& spring) const {
    // Every "if" of the law is a select here, not a jump: the sphere pair
    // loop runs this over several contacts at once as SIMD (and a sliding
    // test that is a coin flip costs no branch misprediction). Each select
    // picks between values computed with the operations of the plain
    // branches, so the results are those of the branching form.
    ContactResult r;
    const double root = std::sqrt(r_eff * delta);
    const double fn = normal_coef_ * root * delta;
    const double kt = tangential_ratio_ * 1.5 * normal_coef_ * root;

    // Rotate the stored force into the current tangent plane, keeping its
    // size (a zero spring stays as it is; one normal to the plane becomes 0).
    const Vec3 old_ft = spring;
    const double old2 = norm2(old_ft);
    Vec3 proj = old_ft;
    proj -= dot(old_ft, n) * n;
    const double new2 = norm2(proj);
    Vec3 rescaled = proj;
    rescaled *= std::sqrt(old2 / (new2 > 0.0 ? new2 : 1.0));
    Vec3 ft = select(old2 > 0.0, select(new2 > 0.0, rescaled, proj), old_ft);
    ft -= kt * d_t;

    // Coulomb cap (eq. 113)
    const double cap = friction_ * fn;
    const double ft2 = norm2(ft);
    const bool sliding = ft2 > cap * cap;
    const double mag = std::sqrt(ft2);  // > cap >= 0 when sliding
    const double kt_or_1 = kt > 0.0 ? kt : 1.0;
    // delta = 0 (possible by rounding at first touch): kt = cap = 0 and the
    // limit of cap (mag - cap) / kt as delta -> 0 is 0 (not 0/0).
    r.friction_dissipation = sliding && kt > 0.0 ? cap * (mag - cap) / kt_or_1 : 0.0;
    Vec3 capped = ft;
    capped *= cap / (sliding ? mag : 1.0);
    ft = select(sliding, capped, ft);
    r.sliding = sliding;
    spring = ft;
    r.normal_force = fn;
    r.force_on_j = fn * n + ft;
    r.elastic_energy = 0.4 * fn * delta + (kt > 0.0 ? 0.5 * norm2(ft) / kt_or_1 : 0.0);
    return r;
  }

 private:
  double normal_coef_ = 0.0;
  double tangential_ratio_ = 0.0;
  double friction_ = 0.0;
};

}  // namespace vt::dem
