// Contact detection between two spheroids (DESIGN §4): overlap, normal and
// contact point for the Hertz law, by the common-normal method.
//
// Inputs: spheroids i and j (semi-axes a, b and orientation, spheroid.h) and
// the branch vector d = x_j - x_i [m] (already the minimum periodic image).
//
// Definition (what is computed). With h_i, h_j the support functions of the
// two bodies (spheroid.h) and n a unit vector,
//     g(n)  = h_i(n) + h_j(n) - n.d                                   [m]
//     delta = min_{|n|=1} g(n)     (signed overlap, > 0 = penetration)
//     n*    = argmin               (unit contact normal, from i to j)
// h_i + h_j is the support function of the Minkowski sum M = E_i (+) E_j, so
// delta is the signed distance from d to the boundary of M: the length of the
// shortest translation of j that brings the two bodies into touch (positive
// inside, negative = gap outside). At n* the gradient condition reads
//     p_i(n*) + p_j(n*) - d = delta n*,
// i.e. the deepest point of i into j, P_i = x_i + p_i(n*), and the deepest point
// of j into i, P_j = x_j - p_j(n*), lie on a common normal of both surfaces and
// P_i - P_j = delta n*: this is the classical "common normal / deepest mutual
// penetration" overlap. Outputs: overlap = delta, normal = n*, contact point =
// midpoint of P_i and P_j relative to x_i, c = (p_i(n*) - p_j(n*) + d)/2
// (= p_i - delta/2 n* at the solution; this form is exactly symmetric in i, j).
//
// Why this overlap for Hertz (small overlaps, delta << b):
//  - it is Hertz's "approach": the relative displacement of the two bodies
//    along the common normal since first touch;
//  - it is exact for spheres: g(n) = R_i + R_j - n.d, minimised at n = d/|d|,
//    delta = R_i + R_j - |d|; and for aligned spheroids: tip to tip 2a - |d|,
//    side to side 2b - |d|, tip to side a + b - |d|;
//  - it is continuous (Lipschitz) in positions and orientations, so the Hertz
//    force is too, and by the envelope theorem d(delta)/dd = -n*,
//    d(delta)/d(theta_i) = p_i x n*, d(delta)/d(theta_j) = p_j x n*: a force
//    F(delta) n* on j and -F(delta) n* on i, applied at c (any point on the line
//    P_i P_j gives the same moments), is exactly the gradient of the Hertz
//    potential U(delta). The normal contact is conservative, also in rotation.
//  The Perram-Wertheim scaling mu = sqrt(F) was not chosen: 1/mu - 1 measures
//  the distance to the boundary of M along the centre line d, not along the
//  normal; it overestimates the approach by 1/cos(angle(d, n*)) (up to 1.7 %
//  for aspect 1.2, where that angle reaches 10 degrees) and a force along the
//  contact normal with that magnitude is not conservative.
//
// Method. Bounding spheres first: |d| >= r_i + r_j (r = max(a, b)) -> no
// contact, cheap exit (overlap = -inf). Otherwise Newton's method on the unit
// sphere for g(n), in the tangent plane (t1, t2) of the current n:
//     gradient  G_a = t_a . (p_i + p_j - d)                          [m]
//     Hessian   H = K_i + K_j - g I                                  [m]
//     K_ab = (b^2/h) (delta_ab + (a^2 - b^2)/h^2 (e.t_a)(e.t_b)),
// K being the tensor of principal radii of curvature of the spheroid at its
// support point (e: symmetry axis); then s = -H^-1 G [rad], n <- (n + s_a t_a)/|.|.
// Near the solution H = K_i + K_j - delta I is positive definite as long as
// delta is below the smallest sum of radii of curvature (>= b_i^2/a_i +
// b_j^2/a_j), far beyond the Hertz range, so convergence is quadratic.
// Start (warm): from the cache, the linear extrapolation (2 n_k - n_k-1)/|.|
// of the last two converged normals (error O(turn per step ^2)), or the last
// normal if only one is known. Start (cold): the normal of the ellipsoid with
// inverse shape matrix A_i^-1 + A_j^-1 along d,
// n0 = (A_i^-1 + A_j^-1)^-1 d / |.| (exact for spheres and aligned pairs).
// Convergence test: the Newton step |s| <= step_tolerance (default 1e-5 rad),
// after which that step is applied and the iteration stops. That last move
// is normalised by one Newton step for 1/|v| (|v|^2 = 1 + |s|^2, error
// ~|s|^4), and the support points there are the ones of the evaluated
// point carried over by the series of sqrt(1 + x) and 1/sqrt(1 + x) to x^3,
// x = (h_new^2 - h^2)/h^2 ~ |s| (error ~x^4, below rounding): a converged
// solve takes two square roots and four divisions in all. Convergence is
// quadratic: the step just applied leaves a normal error ~0.7 |s|^2 <= 1e-10
// (measured on 2000 random pairs of aspect <= 2), and since g is stationary
// at n* the overlap error is ~ (curvature radius) |dn|^2, far below rounding:
// overlap and contact point come out exact to ~1e-15 of b. Acceptance also
// needs H positive definite and delta <= r_i + r_j - |d| + 1e-12 (r_i + r_j),
// an upper bound of g(d/|d|) (h <= r): this rejects a spurious local minimum on
// the far side of M (>~ 2 (b_i + b_j) deep) for aspect ratios up to ~3.
// Fallback (counted in stats.fallbacks) when the plain Newton fails to meet
// these in max_iterations steps (non positive-definite Hessian, too many
// steps, rejected minimum): damped Newton from the better (smaller g) of the
// cold start n0 and d/|d|, with the Hessian replaced by the scalar curvature
// b_i^2/h_i + b_j^2/h_j when not positive definite, each step clamped to
// max_step and backtracked (Armijo) until g decreases. If that also fails the
// best point found is returned with converged = false (stats.failures).
//
// Scale: every tolerance is dimensionless (angles) or relative to the semi-
// axes; every operation is a product, quotient, sum of like lengths or sqrt of
// squared lengths, so the result scales bit for bit under power-of-two
// changes of the length unit. Deterministic (no randomness, fixed order).
// Swapping i and j gives n -> -n and the same overlap (to rounding).
// Cost (one core; tests/unit/test_spheroid_contact.cpp prints it): a Newton
// step is ~90 flops with 2 square roots and 4 divisions on its critical path.
// The pair loop (src/dem/spheroid_pairs.cpp) takes the warm one-step case 8
// pairs at a time (spheroid_warm_lanes.h); for the pairs those hand back it
// first evaluates g at the warm start for its separation certificate and
// passes those support values in (SpheroidStart), so a warm solve repeats
// none of them.
// Warm start: 1 step when the extrapolated normal is within 1e-5 rad (steady
// turning up to 1e-3 rad per step is tested), 2 steps for errors up to
// ~3e-3 rad; cold: 2-4 steps (mean 2.8 for aspect 1-2). Measured on the
// development VM (one dependent sqrt = 7.5 ns there): warm ~110 ns, cold
// ~240 ns, bounding-sphere reject ~18 ns per call (7 flops, no square root,
// plus call overhead). Reentrant: no global state; stats are per caller.
#pragma once

#include <cmath>
#include <cstdint>

#include "virtual_triaxial/dem/spheroid.h"
#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

/// Per-pair warm-start state, updated by every call that is given it. Keep it
/// with the pair's contact history (one call per time step), reset or drop it
/// when the pair leaves the neighbour list. Treat it as opaque.
struct SpheroidContactCache {
  Vec3 normal;                ///< last converged normal, world frame, from i to j
  Vec3 previous;              ///< the one before (if has_previous)
  bool valid = false;         ///< false: cold start next time
  bool has_previous = false;  ///< two consecutive converged solutions: extrapolate
  void reset() { valid = has_previous = false; }
};

/// Counters, summed over calls. Not thread-safe: use one per thread and add().
struct SpheroidContactStats {
  std::uint64_t calls = 0;             ///< calls of detect_spheroid_contact
  std::uint64_t bounding_rejects = 0;  ///< cheap exits by the bounding-sphere test
  std::uint64_t solves = 0;            ///< calls that ran the iteration
  std::uint64_t warm_starts = 0;       ///< solves started from a valid cache
  std::uint64_t iterations = 0;        ///< Newton steps, primary + fallback
  std::uint64_t fallbacks = 0;         ///< solves that needed the fallback
  std::uint64_t failures = 0;          ///< solves returned with converged = false
  std::uint64_t asleep = 0;            ///< pairs in reach skipped as certified apart (contact_forces)
  void add(const SpheroidContactStats& o);
};

struct SpheroidContactOptions {
  int max_iterations = 12;           ///< plain Newton steps before the fallback
  int max_fallback_iterations = 60;  ///< damped Newton steps in the fallback
  double step_tolerance = 1e-5;      ///< convergence: Newton step [rad]
  double max_step = 0.5;             ///< step clamp [rad]
};

/// Result of one detection (see the header comment for the definitions).
struct SpheroidContact {
  double overlap = 0.0;  ///< signed delta [m]; > 0 contact; -inf after the bounding exit
  Vec3 normal;           ///< unit normal n* from i to j (zero after the bounding exit)
  Vec3 contact_point;    ///< c = (P_i + P_j)/2 - x_i = p_i - delta/2 n* [m]
  Vec3 deepest_i;        ///< P_i - x_i = p_i(n*) [m]
  Vec3 deepest_j;        ///< P_j - x_j = -p_j(n*) [m]
  int iterations = 0;    ///< Newton steps used (primary + fallback)
  bool in_bounds = false;  ///< false: bounding spheres apart, nothing else computed
  bool converged = true;
  bool fallback = false;   ///< the fallback path ran
};

/// A spheroid reduced to what the solver needs (spheroid.h):
/// A^-1 = b2 I + k e e^T, support function h(n) = sqrt(b2 + k (e.n)^2) [m].
/// Building it costs one quaternion rotation (e = q (1,0,0)); a caller with
/// many pairs per particle builds it once per particle and step (the pair
/// loop of src/dem/spheroid_pairs.cpp does) and passes it to the overloads below,
/// which give bit for bit the results of the Spheroid overloads.
struct SpheroidSupport {
  double b2 = 0.0;     ///< b^2 [m^2]
  double k = 0.0;      ///< a^2 - b^2 [m^2]
  Vec3 e;              ///< world symmetry axis q (1, 0, 0) (unit)
  double bound = 0.0;  ///< bounding radius max(a, b) [m]

  static SpheroidSupport of(const Spheroid& s) {
    const double b2 = s.b * s.b;
    return {b2, s.a * s.a - b2, s.axis(), s.bounding_radius()};
  }
  /// h(n) for a unit world direction n [m].
  double support(const Vec3& n) const {
    const double c = dot(e, n);
    return std::sqrt(b2 + k * c * c);
  }
};

/// v / |v| for |v|^2 within 1e-6 of 1 by one Newton step for 1/|v|
/// (relative error <= 3/8 (|v|^2 - 1)^2, no square root or division: the
/// Newton moves of a converged solve and the warm starts are of this kind);
/// the exact normalisation otherwise.
inline Vec3 normalized_near_unit(const Vec3& v) {
  const double v2 = norm2(v);
  if (std::fabs(v2 - 1.0) <= 1e-6) return (1.5 - 0.5 * v2) * v;
  return (1.0 / std::sqrt(v2)) * v;
}

/// The Newton start of a warm solve (cache.valid): the linear extrapolation
/// (2 n_k - n_k-1)/|.| of the last two converged normals, which predicts a
/// normal turning at a steady rate to O(rate^2), or the last normal.
inline Vec3 warm_start_normal(const SpheroidContactCache& cache) {
  return cache.has_previous ? normalized_near_unit(2.0 * cache.normal - cache.previous)
                            : normalized_near_unit(cache.normal);
}

/// A warm start with the support values of both bodies there, as the pair
/// loop has them from its separation certificate (the solve then does not
/// compute them again). n must be warm_start_normal(cache).
struct SpheroidStart {
  Vec3 n;          ///< unit start normal
  double ci = 0;   ///< e_i . n
  double hi = 0;   ///< h_i(n) [m]
  double cj = 0;   ///< e_j . n
  double hj = 0;   ///< h_j(n) [m]
  static SpheroidStart at(const SpheroidSupport& si, const SpheroidSupport& sj, const Vec3& n) {
    SpheroidStart s;
    s.n = n;
    s.ci = dot(si.e, n);
    s.hi = std::sqrt(si.b2 + si.k * s.ci * s.ci);
    s.cj = dot(sj.e, n);
    s.hj = std::sqrt(sj.b2 + sj.k * s.cj * s.cj);
    return s;
  }
  /// g(n) = h_i + h_j - n.d [m]: < 0 proves the bodies apart.
  double gap(const Vec3& d) const { return hi + hj - dot(n, d); }
};

/// Separation certificate: g(n) = h_i(n) + h_j(n) - n.d [m] for a unit n.
/// delta = min g <= g(n), so g(n) < 0 proves the bodies apart (no iteration
/// needed); callers try the pair's last normal. Cost: 2 square roots.
inline double spheroid_gap_bound(const SpheroidSupport& si, const SpheroidSupport& sj, const Vec3& d,
                                 const Vec3& n) {
  return si.support(n) + sj.support(n) - dot(n, d);
}
double spheroid_gap_bound(const Spheroid& si, const Spheroid& sj, const Vec3& d, const Vec3& n);

/// Detect the contact of spheroid j (centre x_i + d) with spheroid i (centre x_i).
/// cache may be null (always cold start); stats may be null.
/// start: the warm start with its support values (cache->valid required),
/// or null.
SpheroidContact detect_spheroid_contact(const SpheroidSupport& si, const SpheroidSupport& sj,
                                        const Vec3& d, SpheroidContactCache* cache = nullptr,
                                        SpheroidContactStats* stats = nullptr,
                                        const SpheroidContactOptions& opt = {},
                                        const SpheroidStart* start = nullptr);
SpheroidContact detect_spheroid_contact(const Spheroid& si, const Spheroid& sj, const Vec3& d,
                                        SpheroidContactCache* cache = nullptr,
                                        SpheroidContactStats* stats = nullptr,
                                        const SpheroidContactOptions& opt = {});

}  // namespace vt::dem
