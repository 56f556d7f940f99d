#include "virtual_triaxial/dem/spheroid_contact.h"

#include <cmath>
#include <limits>

namespace vt::dem {

void SpheroidContactStats::add(const SpheroidContactStats& o) {
  calls += o.calls;
  bounding_rejects += o.bounding_rejects;
  solves += o.solves;
  warm_starts += o.warm_starts;
  iterations += o.iterations;
  fallbacks += o.fallbacks;
  failures += o.failures;
  asleep += o.asleep;
}

namespace {

using Body = SpheroidSupport;

inline double support(const Body& s, const Vec3& n) { return s.support(n); }

inline Vec3 support_point(const Body& s, const Vec3& n, double* h_out) {
  const double c = dot(s.e, n);
  const double h = std::sqrt(s.b2 + s.k * c * c);
  *h_out = h;
  return (1.0 / h) * (s.b2 * n + (s.k * c) * s.e);
}

inline Vec3 normalized(const Vec3& v) { return (1.0 / std::sqrt(norm2(v))) * v; }

/// Orthonormal tangent basis of unit n (Duff et al. 2017, branch on sign only).
inline void tangent_basis(const Vec3& n, Vec3& t1, Vec3& t2) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double b = n.x * n.y * a;
  t1 = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
  t2 = {b, sign + n.y * n.y * a, -n.y};
}

/// g(n) = h_i + h_j - n.d.
inline double gap_function(const Body& bi, const Body& bj, const Vec3& d, const Vec3& n) {
  return support(bi, n) + support(bj, n) - dot(n, d);
}

/// g, tangential gradient and Riemannian Hessian at unit n.
struct Local {
  double g;
  double g1, g2;         // gradient in (t1, t2) [m]
  double h00, h01, h11;  // Hessian [m]
  double curv;           // b_i^2/h_i + b_j^2/h_j, scalar curvature scale [m]
  Vec3 t1, t2;
  double c[2], h[2], ih[2];  // per body (i, j): e.n, support h(n) [m], 1/h
};

/// Body `which`'s terms at unit n, given c = e.n and h = h(n).
inline void add_body(const Body& s, double c, double h, const Vec3& t1, const Vec3& t2, Local& l, int which) {
  const double ih = 1.0 / h;
  l.c[which] = c;
  l.h[which] = h;
  l.ih[which] = ih;
  const double e1 = dot(s.e, t1), e2 = dot(s.e, t2);
  // t_a . p = k c (e.t_a) / h
  const double kc = s.k * c * ih;
  l.g += h;
  l.g1 += kc * e1;
  l.g2 += kc * e2;
  // K_ab = (b^2/h) (delta_ab + k/h^2 e_a e_b)
  const double r = s.b2 * ih;
  const double q = r * s.k * (ih * ih);
  l.h00 += r + q * e1 * e1;
  l.h01 += q * e1 * e2;
  l.h11 += r + q * e2 * e2;
  l.curv += r;
}

/// evaluate() with c = e.n and h(n) of both bodies known.
inline Local evaluate_with(const Body& bi, const Body& bj, const Vec3& d, const Vec3& n, double ci, double hi,
                           double cj, double hj) {
  Local l{};
  tangent_basis(n, l.t1, l.t2);
  add_body(bi, ci, hi, l.t1, l.t2, l, 0);
  add_body(bj, cj, hj, l.t1, l.t2, l, 1);
  l.g -= dot(n, d);
  l.g1 -= dot(l.t1, d);
  l.g2 -= dot(l.t2, d);
  l.h00 -= l.g;
  l.h11 -= l.g;
  return l;
}

inline Local evaluate(const Body& bi, const Body& bj, const Vec3& d, const Vec3& n) {
  const double ci = dot(bi.e, n), cj = dot(bj.e, n);
  return evaluate_with(bi, bj, d, n, ci, std::sqrt(bi.b2 + bi.k * ci * ci), cj, std::sqrt(bj.b2 + bj.k * cj * cj));
}

/// Newton step s = -H^-1 G; false if H is not positive definite.
inline bool newton_step(const Local& l, double& s1, double& s2) {
  const double det = l.h00 * l.h11 - l.h01 * l.h01;
  if (!(l.h00 > 0.0 && l.h11 > 0.0 && det > 0.0)) return false;
  const double idet = 1.0 / det;
  s1 = (l.h01 * l.g2 - l.h11 * l.g1) * idet;
  s2 = (l.h01 * l.g1 - l.h00 * l.g2) * idet;
  return std::isfinite(s1) && std::isfinite(s2);
}

inline void clamp_step(double& s1, double& s2, double max_step) {
  const double s_2 = s1 * s1 + s2 * s2;
  if (s_2 > max_step * max_step) {
    const double f = max_step / std::sqrt(s_2);
    s1 *= f;
    s2 *= f;
  }
}

inline Vec3 move(const Local& l, const Vec3& n, double s1, double s2) {
  return normalized_near_unit(n + s1 * l.t1 + s2 * l.t2);
}

/// Support point p(n) and h(n) of body `which` at the unit n reached by a
/// converged Newton step from the point evaluated in l: with x = (h(n)^2 -
/// h_l^2)/h_l^2 = k (c^2 - c_l^2)/h_l^2 (|x| ~ the step, <= 1e-5 or so),
/// h = h_l sqrt(1 + x) and 1/h by their series to x^3 (error < x^4, far
/// below rounding), instead of a square root and a division; exact when
/// |x| > 1e-4.
inline Vec3 support_point_near(const Body& s, const Vec3& n, const Local& l, int which, double* h_out) {
  const double c = dot(s.e, n);
  const double cl = l.c[which], ihl = l.ih[which];
  const double x = s.k * (c - cl) * (c + cl) * (ihl * ihl);
  if (!(std::fabs(x) <= 1e-4)) return support_point(s, n, h_out);
  *h_out = l.h[which] * (1.0 + x * (0.5 + x * (-0.125 + x * 0.0625)));
  const double ih = ihl * (1.0 + x * (-0.5 + x * (0.375 - x * 0.3125)));
  return ih * (s.b2 * n + (s.k * c) * s.e);
}

/// Plain Newton. Returns true when the step test is met with H positive
/// definite; n holds the last iterate either way, and *last the evaluation
/// the last step was taken from.
/// `first`: the evaluation at the starting n when the caller has it, or null.
bool plain_newton(const Body& bi, const Body& bj, const Vec3& d, Vec3& n, int max_it, double tol,
                  double max_step, int& iterations, Local* last, const Local* first) {
  for (int it = 0; it < max_it; ++it) {
    *last = (it == 0 && first) ? *first : evaluate(bi, bj, d, n);
    const Local& l = *last;
    double s1, s2;
    if (!newton_step(l, s1, s2)) return false;
    ++iterations;
    const bool done = s1 * s1 + s2 * s2 <= tol * tol;
    clamp_step(s1, s2, max_step);
    n = move(l, n, s1, s2);
    if (done) return true;
  }
  return false;
}

/// Damped Newton with Armijo backtracking on g.
bool damped_newton(const Body& bi, const Body& bj, const Vec3& d, Vec3& n, int max_it, double tol,
                   double max_step, int& iterations) {
  for (int it = 0; it < max_it; ++it) {
    const Local l = evaluate(bi, bj, d, n);
    double s1, s2;
    const bool pd = newton_step(l, s1, s2);
    if (!pd) {  // steepest descent scaled by the curvature scale (a length)
      s1 = -l.g1 / l.curv;
      s2 = -l.g2 / l.curv;
    }
    ++iterations;
    if (pd && s1 * s1 + s2 * s2 <= tol * tol) {
      n = move(l, n, s1, s2);
      return true;
    }
    clamp_step(s1, s2, max_step);
    const double slope = l.g1 * s1 + l.g2 * s2;  // < 0: descent direction [m rad]
    bool moved = false;
    for (int k = 0; k < 40; ++k) {
      const Vec3 trial = move(l, n, s1, s2);
      if (gap_function(bi, bj, d, trial) <= l.g + 1e-4 * slope) {
        n = trial;
        moved = true;
        break;
      }
      s1 *= 0.5;
      s2 *= 0.5;
    }
    if (!moved) return pd;  // no decrease possible at all: rounding floor
  }
  return false;
}

}  // namespace

double spheroid_gap_bound(const Spheroid& si, const Spheroid& sj, const Vec3& d, const Vec3& n) {
  return gap_function(Body::of(si), Body::of(sj), d, n);
}

SpheroidContact detect_spheroid_contact(const Spheroid& si, const Spheroid& sj, const Vec3& d,
                                        SpheroidContactCache* cache, SpheroidContactStats* stats,
                                        const SpheroidContactOptions& opt) {
  return detect_spheroid_contact(Body::of(si), Body::of(sj), d, cache, stats, opt);
}

SpheroidContact detect_spheroid_contact(const SpheroidSupport& bi, const SpheroidSupport& bj,
                                        const Vec3& d, SpheroidContactCache* cache,
                                        SpheroidContactStats* stats, const SpheroidContactOptions& opt,
                                        const SpheroidStart* start) {
  SpheroidContactStats local_stats;
  SpheroidContactStats& st = stats ? *stats : local_stats;
  ++st.calls;

  const double reach = bi.bound + bj.bound;
  const double d2 = norm2(d);
  if (d2 >= reach * reach) {
    ++st.bounding_rejects;
    SpheroidContact out;
    out.overlap = -std::numeric_limits<double>::infinity();
    return out;
  }
  ++st.solves;

  const double tol = opt.step_tolerance;

  // Acceptance bound: delta <= g(d/|d|) <= r_i + r_j - |d| (h <= r), i.e.
  // |d| <= reach (1 + 1e-12) - delta, tested in squares (no square root).
  auto within_bound = [&](double delta) {
    const double rhs = reach + 1e-12 * reach - delta;
    return rhs >= 0.0 && d2 <= rhs * rhs;
  };

  // Cold start: n0 = (A_i^-1 + A_j^-1)^-1 d / |.| = adj(B) d / |.| (B is
  // positive definite, det B > 0).
  auto cold_start = [&]() -> Vec3 {
    if (!(d2 > 0.0)) {  // coincident centres: any direction normal to e_i
      Vec3 t1, t2;
      tangent_basis(bi.e, t1, t2);
      return t1;
    }
    Mat3 b = bi.k * outer(bi.e, bi.e) + bj.k * outer(bj.e, bj.e);
    const double diag = bi.b2 + bj.b2;
    for (int r = 0; r < 3; ++r) b.m[r][r] += diag;
    const Vec3 c0 = cross(b.column(1), b.column(2));  // rows of adj(B)
    const Vec3 c1 = cross(b.column(2), b.column(0));
    const Vec3 c2 = cross(b.column(0), b.column(1));
    const Vec3 v{dot(c0, d), dot(c1, d), dot(c2, d)};
    const double v2 = norm2(v);
    return (std::isfinite(v2) && v2 > 0.0) ? normalized(v) : normalized(d);
  };

  const bool warm = cache && cache->valid;
  Vec3 n;
  Local first;
  const bool have_first = warm && start;
  if (warm) {
    ++st.warm_starts;
    if (have_first) {
      n = start->n;
      first = evaluate_with(bi, bj, d, n, start->ci, start->hi, start->cj, start->hj);
    } else {
      n = warm_start_normal(*cache);
    }
  } else {
    n = cold_start();
  }

  int iterations = 0;
  Local last;
  bool ok = plain_newton(bi, bj, d, n, opt.max_iterations, tol, opt.max_step, iterations, &last,
                         have_first ? &first : nullptr);
  double hi, hj;
  Vec3 pi, pj;
  if (ok) {  // n is one converged (small) step from the point `last` was evaluated at
    pi = support_point_near(bi, n, last, 0, &hi);
    pj = support_point_near(bj, n, last, 1, &hj);
  } else {
    pi = support_point(bi, n, &hi);
    pj = support_point(bj, n, &hj);
  }
  double delta = hi + hj - dot(n, d);
  ok = ok && within_bound(delta);

  bool fallback = false;
  if (!ok) {
    ++st.fallbacks;
    fallback = true;
    Vec3 start = cold_start();
    if (d2 > 0.0) {  // the better of the cold start and the centre line
      const Vec3 dhat = normalized(d);
      if (gap_function(bi, bj, d, dhat) < gap_function(bi, bj, d, start)) start = dhat;
    }
    n = start;
    ok = damped_newton(bi, bj, d, n, opt.max_fallback_iterations, tol, opt.max_step, iterations);
    pi = support_point(bi, n, &hi);
    pj = support_point(bj, n, &hj);
    delta = hi + hj - dot(n, d);
    ok = ok && within_bound(delta);
  }

  st.iterations += static_cast<std::uint64_t>(iterations);
  if (!ok) ++st.failures;
  if (cache) {
    // extrapolate next time only from two consecutive plain-Newton solutions
    cache->has_previous = ok && cache->valid && !fallback;
    cache->previous = cache->normal;
    cache->normal = n;
    cache->valid = ok;
  }

  // Built last, after every store through stats and cache (which the
  // compiler must assume may alias the result), so it is written only once.
  SpheroidContact out;
  out.in_bounds = true;
  out.fallback = fallback;
  out.overlap = delta;
  out.normal = n;
  out.deepest_i = pi;
  out.deepest_j = -pj;
  out.contact_point = 0.5 * ((pi - pj) + d);  // (P_i + P_j)/2 - x_i, symmetric in i, j
  out.iterations = iterations;
  out.converged = ok;
  return out;
}

}  // namespace vt::dem
