// One contact's term of the packing's axis stiffness (axis_stiffness.h):
//   M_i = (1/V) sum_c d_i^2 (K_n n_i^2 + K_t (1 - n_i^2))   [Pa]
// with branch d [m] (owner to partner), n = d / |d|, the Hertz tangent
// normal stiffness K_n = 3/2 F.n / delta [N/m] (eq. 115-116; delta = 2 x the
// half overlap) and K_t = 2 (1 - nu) / (2 - nu) K_n (eq. 114). Shared by the
// pass over the neighbour list (axis_stiffness.cpp) and the contact sums of a
// measured force evaluation (ContactSums::axis_stiffness_sum), so both use
// one formula.
#pragma once

#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

/// Factors of one contact's term: per axis a, d_a^2 [m^2] and
/// K_n n_a^2 + K_t (1 - n_a^2) [N/m]; `none`: no term (not in contact, or
/// coincident centres: no direction).
struct AxisStiffnessTerm {
  Vec3 d2;
  Vec3 stiffness;
  bool none;
};

/// d: branch [m]; f: contact force on the partner [N]; half_overlap [m];
/// kt_ratio = K_t / K_n (HertzMindlin::tangential_ratio). Written without
/// jumps so that a loop over contacts runs as SIMD.
inline AxisStiffnessTerm axis_stiffness_term(const Vec3& d, const Vec3& f, double half_overlap, double kt_ratio) {
  const double dist = norm(d);
  const Vec3 n = (1.0 / dist) * d;
  const double kn = 1.5 * dot(f, n) / (2.0 * half_overlap);
  const double kt = kt_ratio * kn;
  return {{d.x * d.x, d.y * d.y, d.z * d.z},
          {kn * n.x * n.x + kt * (1.0 - n.x * n.x), kn * n.y * n.y + kt * (1.0 - n.y * n.y),
           kn * n.z * n.z + kt * (1.0 - n.z * n.z)},
          !((half_overlap > 0.0) & (dist > 0.0))};
}

}  // namespace vt::dem
