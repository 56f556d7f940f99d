// The warm one-step solve of the spheroid contact (spheroid_contact.h) for
// up to sixteen pairs at a time, as SIMD: the common case of a loaded
// packing, where the extrapolated normal of the pair's cache is within the
// step tolerance after one Newton step.
//
// Per lane (pair i, j with branch d = x_j - x_i [m], the bodies' support data
// and the pair's cache), the same formulas as detect_spheroid_contact's warm
// path, DESIGN §4, without its branches:
//   start    n0 = (2 n_k - n_k-1)/|.| (or n_k) by one Newton step for 1/|v|
//   support  h(n) = sqrt(b^2 + k (e.n)^2),  g(n0) = h_i + h_j - n0.d     [m]
//   apart    g(n0) < 0 proves delta < 0 (the separation certificate)
//   Newton   G_a = t_a.(p_i + p_j - d),  H = K_i + K_j - g I,
//            K_ab = (b^2/h)(delta_ab + k/h^2 (e.t_a)(e.t_b)),  s = -H^-1 G
//   accept   H positive definite and |s| <= step tolerance; then
//            n* = (n0 + s_a t_a)/|.|, p(n*) from the series of h about n0,
//            delta = h_i + h_j - n*.d, c = (p_i - p_j + d)/2
//            and delta <= (r_i + r_j)(1 + 1e-12) - |d| (the far-side check,
//            r = max(a, b)).
// Outcome per lane: Apart (gap = -g(n0) > 0), Solved (delta, n*, c; the
// solve counts one warm Newton step) or Scalar: the start or the result is
// outside what one step covers (|v|^2 of the start or of the stepped normal
// not within 1e-6 of 1, H not positive definite, step above the tolerance
// or not finite, series out of range, far-side check failed, bounding
// spheres apart), and the caller runs detect_spheroid_contact instead,
// which restarts from the cache.
//
// A lane's result depends only on its own inputs (every lane runs the same
// operations; the caller fills unused lanes with copies), so a pair gets the
// same bits whichever group or thread takes it. They agree with
// detect_spheroid_contact's to rounding (the compiler fuses multiply-adds
// differently in the two), which tests/unit/test_spheroid_warm_lanes.cpp
// checks on moving pairs, with the Apart and Scalar outcomes (a stale start,
// a start off unit length, a maximum of g with H not positive definite,
// bounding spheres apart) and the independence of the lanes.
#pragma once

#include <cstdint>

#include "virtual_triaxial/dem/spheroid_contact.h"
#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

/// What the warm lanes found for one pair.
enum class WarmOutcome : std::int32_t { Apart = 0, Solved = 1, Scalar = 2 };

/// Sixteen pairs, field by field. Fill lanes with set() (or the bodies'
/// fields directly and set_pair(), as the pair loop does); run
/// solve_spheroid_warm_lanes(); read the outputs.
struct SpheroidWarmLanes {
  /// Also the spheroid pair loop's group size (spheroid_pairs.cpp). Two
  /// 8-double SIMD registers per field: the warm solve and the contact law
  /// are chains of dependent square roots and divisions, and two independent
  /// chains per group keep the core busy while each waits (0.946-0.952 of
  /// the cost of 8 lanes on one thread, 12 000 spheroids, same bits; 24
  /// lanes 0.950, 32 lanes 1.024: session 33).
  static constexpr int kLanes = 16;
  // inputs
  double dx[kLanes], dy[kLanes], dz[kLanes];            ///< branch d [m]
  double bi2[kLanes], ki[kLanes], bound_i[kLanes];      ///< body i: b^2, a^2 - b^2 [m^2], max(a, b) [m]
  double eix[kLanes], eiy[kLanes], eiz[kLanes];         ///< body i: symmetry axis (unit)
  double bj2[kLanes], kj[kLanes], bound_j[kLanes];      ///< body j
  double ejx[kLanes], ejy[kLanes], ejz[kLanes];
  double nx[kLanes], ny[kLanes], nz[kLanes];            ///< cache: last normal
  double mx[kLanes], my[kLanes], mz[kLanes];            ///< cache: the one before, = last when none
  // outputs
  double code[kLanes];                                  ///< the outcome as 0, 1, 2 (see outcome())
  double gap[kLanes];                                   ///< Apart: -g(n0) > 0 [m]
  double delta[kLanes];                                 ///< Solved: signed overlap [m]
  double ox[kLanes], oy[kLanes], oz[kLanes];            ///< Solved: normal n* (i -> j)
  double cx[kLanes], cy[kLanes], cz[kLanes];            ///< Solved: contact point relative to x_i [m]

  /// Lane k: bodies, branch and a valid cache (cache.valid must be true).
  void set(int k, const SpheroidSupport& si, const SpheroidSupport& sj, const Vec3& d,
           const SpheroidContactCache& cache) {
    bi2[k] = si.b2; ki[k] = si.k; bound_i[k] = si.bound;
    eix[k] = si.e.x; eiy[k] = si.e.y; eiz[k] = si.e.z;
    bj2[k] = sj.b2; kj[k] = sj.k; bound_j[k] = sj.bound;
    ejx[k] = sj.e.x; ejy[k] = sj.e.y; ejz[k] = sj.e.z;
    set_pair(k, d, cache);
  }
  /// Lane k without the bodies (set by the caller, e.g. body_lanes of
  /// pair_body.h into the fields of body_i and body_j): branch and cache.
  void set_pair(int k, const Vec3& d, const SpheroidContactCache& cache) {
    dx[k] = d.x; dy[k] = d.y; dz[k] = d.z;
    nx[k] = cache.normal.x; ny[k] = cache.normal.y; nz[k] = cache.normal.z;
    const Vec3 m = cache.has_previous ? cache.previous : cache.normal;
    mx[k] = m.x; my[k] = m.y; mz[k] = m.z;
  }
  /// Copies lane `from` into lane `to` (fills the unused lanes of a group).
  void repeat(int from, int to);
  WarmOutcome outcome(int k) const { return static_cast<WarmOutcome>(static_cast<int>(code[k])); }
  Vec3 normal(int k) const { return {ox[k], oy[k], oz[k]}; }
  Vec3 contact_point(int k) const { return {cx[k], cy[k], cz[k]}; }
};

/// Every lane's warm one-step solve (header comment); step_tolerance [rad]
/// as SpheroidContactOptions::step_tolerance, below max_step.
void solve_spheroid_warm_lanes(SpheroidWarmLanes& lanes, double step_tolerance);

/// A pair's cache after a Solved lane with delta > 0 (as detect_spheroid_contact
/// leaves it after a converged warm solve): the new normal, the last one kept.
inline void advance_cache(SpheroidContactCache& cache, const Vec3& normal) {
  cache.previous = cache.normal;
  cache.normal = normal;
  cache.has_previous = true;
  cache.valid = true;
}

}  // namespace vt::dem
