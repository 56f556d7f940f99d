// Spheroid geometry and spheroid-spheroid contact detection (spheroid.h,
// spheroid_contact.h) against closed forms, an independent brute-force
// long-double reference, symmetry and scaling properties.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include "virtual_triaxial/dem/spheroid.h"
#include "virtual_triaxial/dem/spheroid_contact.h"

using namespace vt::dem;

namespace {

// ---- deterministic random numbers ----------------------------------------
struct Rng {
  std::mt19937_64 g;
  explicit Rng(std::uint64_t seed) : g(seed) {}
  double uniform() { return static_cast<double>(g() >> 11) * 0x1.0p-53; }  // [0,1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  Vec3 direction() {  // uniform on the unit sphere
    const double z = uniform(-1.0, 1.0), phi = uniform(0.0, 2.0 * M_PI);
    const double r = std::sqrt(1.0 - z * z);
    return {r * std::cos(phi), r * std::sin(phi), z};
  }
  Quaternion rotation() {  // uniform random rotation (Shoemake)
    const double u1 = uniform(), u2 = uniform(0.0, 2.0 * M_PI), u3 = uniform(0.0, 2.0 * M_PI);
    const double s1 = std::sqrt(1.0 - u1), s2 = std::sqrt(u1);
    return {s1 * std::sin(u2), s1 * std::cos(u2), s2 * std::sin(u3), s2 * std::cos(u3)};
  }
};

Quaternion axis_rotation(const Vec3& u, double phi) {
  const double s = std::sin(0.5 * phi);
  return {std::cos(0.5 * phi), s * u.x, s * u.y, s * u.z};
}

/// Orientation whose body x axis is the unit vector u.
Quaternion x_axis_to(const Vec3& u) {
  const Vec3 x{1, 0, 0};
  const double c = dot(x, u);
  const Vec3 ax = cross(x, u);
  const double s = norm(ax);
  if (s < 1e-300) return c > 0 ? Quaternion{} : Quaternion{0, 0, 0, 1};
  return axis_rotation((1.0 / s) * ax, std::atan2(s, c));
}

/// A unit vector perpendicular to unit n.
Vec3 normalized_perp(const Vec3& n) {
  const Vec3 r = std::fabs(n.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 t = r - dot(r, n) * n;
  return (1.0 / norm(t)) * t;
}

double max_abs(const Vec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

// ---- independent long-double reference ---------------------------------------
// Written without spheroid.h: full rotation matrix from the quaternion, full
// inverse shape matrix R diag(a^2, b^2, b^2) R^T, support function
// sqrt(n^T A^-1 n); delta = min over the unit sphere of h_i + h_j - n.d by
// dense sampling and a shrinking pattern search.
using LD = long double;
struct V3 {
  LD x, y, z;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(LD s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
LD dotl(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 unit(V3 a) { return (1.0L / std::sqrt(dotl(a, a))) * a; }
V3 to_l(const Vec3& v) { return {v.x, v.y, v.z}; }

struct RefBody {
  LD m[3][3];  // A^-1
  V3 support_point(V3 n) const {
    V3 an{m[0][0] * n.x + m[0][1] * n.y + m[0][2] * n.z, m[1][0] * n.x + m[1][1] * n.y + m[1][2] * n.z,
          m[2][0] * n.x + m[2][1] * n.y + m[2][2] * n.z};
    return (1.0L / std::sqrt(dotl(n, an))) * an;
  }
  LD support(V3 n) const { return dotl(n, support_point(n)); }
};

RefBody ref_body(const Spheroid& s) {
  const LD w = s.q.w, x = s.q.x, y = s.q.y, z = s.q.z;
  const LD nq = std::sqrt(w * w + x * x + y * y + z * z);
  const LD qw = w / nq, qx = x / nq, qy = y / nq, qz = z / nq;
  const LD r[3][3] = {{1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qw * qz), 2 * (qx * qz + qw * qy)},
                      {2 * (qx * qy + qw * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qw * qx)},
                      {2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx * qx + qy * qy)}};
  const LD dg[3] = {LD(s.a) * s.a, LD(s.b) * s.b, LD(s.b) * s.b};
  RefBody b;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      b.m[i][j] = 0;
      for (int k = 0; k < 3; ++k) b.m[i][j] += r[i][k] * dg[k] * r[j][k];
    }
  return b;
}

struct RefResult {
  LD overlap;
  V3 normal;
};

RefResult brute_force(const Spheroid& si, const Spheroid& sj, const Vec3& dd) {
  const RefBody bi = ref_body(si), bj = ref_body(sj);
  const V3 d = to_l(dd);
  auto g = [&](V3 n) { return bi.support(n) + bj.support(n) - dotl(n, d); };
  // Fibonacci sphere, 20000 points.
  const int N = 20000;
  const LD golden = M_PI * (3.0L - std::sqrt(5.0L));
  V3 best{0, 0, 1};
  LD gbest = g(best);
  for (int k = 0; k < N; ++k) {
    const LD z = 1.0L - (2.0L * k + 1.0L) / N;
    const LD r = std::sqrt(1.0L - z * z);
    const V3 n{r * std::cos(golden * k), r * std::sin(golden * k), z};
    const LD gv = g(n);
    if (gv < gbest) {
      gbest = gv;
      best = n;
    }
  }
  // Pattern search on the tangent plane, 8 directions, shrinking step.
  for (LD step = 0.05L; step > 1e-14L;) {
    const V3 ref = std::fabs(best.x) < 0.6L ? V3{1, 0, 0} : V3{0, 1, 0};
    const V3 t1 = unit(ref - dotl(ref, best) * best);
    const V3 t2{best.y * t1.z - best.z * t1.y, best.z * t1.x - best.x * t1.z, best.x * t1.y - best.y * t1.x};
    bool improved = false;
    for (int k = 0; k < 8; ++k) {
      const LD ang = k * M_PI / 4;
      const V3 n = unit(best + (step * std::cos(ang)) * t1 + (step * std::sin(ang)) * t2);
      const LD gv = g(n);
      if (gv < gbest) {
        gbest = gv;
        best = n;
        improved = true;
      }
    }
    if (!improved) step *= 0.5L;
  }
  return {gbest, best};
}

/// Exact inverse construction: for a unit normal n, y = p_i(n) + p_j(n) is the
/// point of the Minkowski sum's boundary with outward normal n; the branch
/// vector d = y - delta n then has overlap delta and normal n (delta below the
/// smallest radius of curvature of the boundary).
struct Constructed {
  Vec3 d;
  V3 normal, contact;
  LD overlap;
};
Constructed construct(const Spheroid& si, const Spheroid& sj, const Vec3& n, double delta) {
  const RefBody bi = ref_body(si), bj = ref_body(sj);
  const V3 nl = unit(to_l(n));
  const V3 pi = bi.support_point(nl), pj = bj.support_point(nl);
  const V3 d = pi + pj - LD(delta) * nl;
  Constructed c;
  c.d = {double(d.x), double(d.y), double(d.z)};
  c.normal = nl;
  c.overlap = delta;
  c.contact = pi - (LD(delta) / 2) * nl;
  return c;
}

LD dist(V3 a, const Vec3& b) { return std::sqrt(dotl(a - to_l(b), a - to_l(b))); }

struct RandomPair {
  Spheroid si, sj;
  Vec3 n;
  double delta, bmin;
};
RandomPair random_pair(Rng& rng, double b0) {
  RandomPair p;
  const double bi = b0 * rng.uniform(0.6, 1.4), bj = b0 * rng.uniform(0.6, 1.4);
  p.si = Spheroid(bi * rng.uniform(1.0, 2.0), bi, rng.rotation());
  p.sj = Spheroid(bj * rng.uniform(1.0, 2.0), bj, rng.rotation());
  p.bmin = std::min(bi, bj);
  p.delta = p.bmin * std::pow(10.0, rng.uniform(-4.0, -2.0));
  p.n = rng.direction();
  return p;
}

}  // namespace

// ---- spheroid.h ------------------------------------------------------------------

TEST(Spheroid, MassPropertiesMatchClosedForms) {
  const double a = 1.2e-3, b = 1e-3, rho = 2650;
  const Spheroid s(a, b, Rng(3).rotation());
  EXPECT_DOUBLE_EQ(s.volume(), 4.0 / 3.0 * M_PI * a * b * b);
  EXPECT_DOUBLE_EQ(s.nominal_radius(), std::cbrt(a * b * b));
  EXPECT_DOUBLE_EQ(s.average_radius(), (a + 2 * b) / 3);
  EXPECT_EQ(s.bounding_radius(), a);
  EXPECT_EQ(s.minor_semi_axis(), b);
  const double m = rho * 4.0 / 3.0 * M_PI * a * b * b;
  EXPECT_DOUBLE_EQ(s.mass(rho), m);
  const Vec3 in = s.principal_inertia(rho);
  EXPECT_DOUBLE_EQ(in.x, 0.4 * m * b * b);
  EXPECT_DOUBLE_EQ(in.y, 0.2 * m * (a * a + b * b));
  EXPECT_EQ(in.y, in.z);
  const Spheroid sp(b, b);  // sphere limit
  EXPECT_DOUBLE_EQ(sp.nominal_radius(), b);
  EXPECT_DOUBLE_EQ(sp.average_radius(), b);
  EXPECT_DOUBLE_EQ(sp.principal_inertia(rho).y, 0.4 * sp.mass(rho) * b * b);
}

TEST(Spheroid, ShapeMatrixSupportAndSurface) {
  Rng rng(5);
  for (int c = 0; c < 50; ++c) {
    const double b = rng.uniform(0.5, 2.0), a = b * rng.uniform(1.0, 2.0);
    const Spheroid s(a, b, rng.rotation());
    const Mat3 p = s.shape_matrix() * s.inverse_shape_matrix();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(p(i, j), i == j ? 1.0 : 0.0, 1e-14);
    // A = R diag(1/a^2, 1/b^2, 1/b^2) R^T: the body axes are eigenvectors
    const Vec3 ex = s.q.rotate({1, 0, 0}), ey = s.q.rotate({0, 1, 0});
    const Vec3 ax = s.shape_matrix() * ex, ay = s.shape_matrix() * ey;
    EXPECT_LT(max_abs(ax - (1 / (a * a)) * ex) * a * a, 1e-14);
    EXPECT_LT(max_abs(ay - (1 / (b * b)) * ey) * b * b, 1e-14);
    EXPECT_NEAR(s.level(a * ex), 1.0, 1e-14);
    EXPECT_NEAR(s.level(b * ey), 1.0, 1e-14);
    // support point: on the surface, outward normal n, h = n.p
    const Vec3 n = rng.direction();
    const Vec3 sp = s.support_point(n);
    EXPECT_NEAR(s.level(sp), 1.0, 1e-14);
    const Vec3 grad = s.shape_matrix() * sp;
    EXPECT_LT(norm(cross(grad, n)) / norm(grad), 1e-14);
    EXPECT_GT(dot(grad, n), 0.0);
    EXPECT_NEAR(s.support(n), dot(n, sp), 1e-14 * a);
  }
}

// ---- aligned pairs: closed forms ---------------------------------------------------

namespace {
/// Check one aligned configuration: overlap `expected`, normal u, contact at
/// (reach_i - expected/2) u from x_i; tolerances 1e-10 of the minor semi-axis.
void expect_aligned(const Spheroid& si, const Spheroid& sj, const Vec3& u, double s, double reach_i,
                    double reach_j) {
  const Vec3 d = s * u;
  const double expected = reach_i + reach_j - s;
  const SpheroidContact c = detect_spheroid_contact(si, sj, d);
  const double bmin = std::min(si.minor_semi_axis(), sj.minor_semi_axis());
  const double reach = si.bounding_radius() + sj.bounding_radius();
  if (norm2(d) >= reach * reach) {  // tip to tip with a gap (or just touching)
    EXPECT_FALSE(c.in_bounds);
    return;
  }
  ASSERT_TRUE(c.in_bounds);
  EXPECT_TRUE(c.converged);
  EXPECT_FALSE(c.fallback);
  EXPECT_NEAR(c.overlap, expected, 1e-10 * bmin);
  EXPECT_LT(max_abs(c.normal - u), 1e-10);
  EXPECT_LT(max_abs(c.contact_point - (reach_i - 0.5 * expected) * u), 1e-10 * bmin);
  EXPECT_LT(max_abs(c.deepest_i - reach_i * u), 1e-10 * bmin);
  EXPECT_LT(max_abs(c.deepest_j - (-reach_j) * u), 1e-10 * bmin);
}
}  // namespace

TEST(SpheroidContact, AlignedClosedForms) {
  const double b = 1e-3, a = 1.2e-3, b2 = 0.8e-3, a2 = 1.1e-3;
  Rng rng(11);
  for (int c = 0; c < 20; ++c) {
    // A random frame (u along the branch vector, v and w across it).
    const Quaternion frame = c == 0 ? Quaternion{} : rng.rotation();
    const Vec3 u = frame.rotate({1, 0, 0}), v = frame.rotate({0, 1, 0}), w = frame.rotate({0, 0, 1});
    for (double frac : {1e-4, 1e-3, 1e-2, 0.0, -1e-3}) {  // overlap / b; <0 = gap
      // tip to tip: both symmetry axes along u
      {
        const Spheroid si(a, b, x_axis_to(u)), sj(a2, b2, x_axis_to(-1.0 * u));
        expect_aligned(si, sj, u, a + a2 - frac * b2, a, a2);
      }
      // side by side, axes parallel (along v) and crossed (v, w)
      {
        const Spheroid si(a, b, x_axis_to(v)), sj(a2, b2, x_axis_to(v));
        expect_aligned(si, sj, u, b + b2 - frac * b2, b, b2);
        const Spheroid sk(a2, b2, x_axis_to(w));
        expect_aligned(si, sk, u, b + b2 - frac * b2, b, b2);
      }
      // tip (i) to side (j)
      {
        const Spheroid si(a, b, x_axis_to(u)), sj(a2, b2, x_axis_to(w));
        expect_aligned(si, sj, u, a + b2 - frac * b2, a, b2);
        expect_aligned(sj, si, -1.0 * u, a + b2 - frac * b2, b2, a);
      }
    }
  }
}

TEST(SpheroidContact, BoundingSphereExitAndGap) {
  SpheroidContactStats st;
  const Spheroid si(1.2, 1.0), sj(1.2, 1.0, x_axis_to({0, 1, 0}));
  const SpheroidContact far = detect_spheroid_contact(si, sj, {2.4, 0, 0}, nullptr, &st);
  EXPECT_FALSE(far.in_bounds);
  EXPECT_TRUE(std::isinf(far.overlap) && far.overlap < 0);
  EXPECT_EQ(st.bounding_rejects, 1u);
  EXPECT_EQ(st.solves, 0u);
  // inside the bounding spheres but apart: tip-to-side gap 2.3 - 2.2 = 0.1
  const SpheroidContact gap = detect_spheroid_contact(si, sj, {2.3, 0, 0}, nullptr, &st);
  EXPECT_TRUE(gap.in_bounds);
  EXPECT_TRUE(gap.converged);
  EXPECT_NEAR(gap.overlap, -0.1, 1e-13);
  EXPECT_EQ(st.solves, 1u);
}

TEST(SpheroidContact, CoincidentCentresGiveMinorAxesSum) {
  // d = 0: delta = min_n h_i(n) + h_j(n) = b_i + b_j, for n normal to both axes.
  Rng rng(19);
  for (int c = 0; c < 20; ++c) {
    const Spheroid si(1.3, 1.0, rng.rotation()), sj(1.5, 0.7, rng.rotation());
    const SpheroidContact r = detect_spheroid_contact(si, sj, Vec3{});
    ASSERT_TRUE(r.in_bounds);
    EXPECT_TRUE(r.converged);
    EXPECT_NEAR(r.overlap, 1.7, 1e-12);
    EXPECT_LT(std::fabs(dot(r.normal, si.axis())), 1e-6);
    EXPECT_LT(std::fabs(dot(r.normal, sj.axis())), 1e-6);
  }
}

// ---- random orientations against the references -------------------------------

TEST(SpheroidContact, RandomPairsMatchBruteForceAndConstruction) {
  Rng rng(2024);
  SpheroidContactStats st;
  double worst_overlap = 0, worst_normal = 0, worst_point = 0, worst_bf = 0;
  int max_it = 0;
  const int cases = 200;
  for (int c = 0; c < cases; ++c) {
    const RandomPair p = random_pair(rng, 1e-3);
    const Constructed ref = construct(p.si, p.sj, p.n, p.delta);
    const SpheroidContact r = detect_spheroid_contact(p.si, p.sj, ref.d, nullptr, &st);
    ASSERT_TRUE(r.converged) << "case " << c;
    max_it = std::max(max_it, r.iterations);
    // constructed (exact) reference
    const double e_ov = std::fabs(double(r.overlap - ref.overlap)) / p.bmin;
    const double e_n = double(dist(ref.normal, r.normal));
    const double e_c = double(dist(ref.contact, r.contact_point)) / p.bmin;
    worst_overlap = std::max(worst_overlap, e_ov);
    worst_normal = std::max(worst_normal, e_n);
    worst_point = std::max(worst_point, e_c);
    EXPECT_LT(e_ov, 1e-10) << "case " << c;
    EXPECT_LT(e_n, 1e-9) << "case " << c;
    EXPECT_LT(e_c, 1e-9) << "case " << c;
    // brute-force reference (independent minimisation)
    const RefResult bf = brute_force(p.si, p.sj, ref.d);
    const double e_bf = std::max(std::fabs(double(bf.overlap - r.overlap)) / p.bmin,
                                 double(dist(bf.normal, r.normal)));
    worst_bf = std::max(worst_bf, e_bf);
    EXPECT_LT(std::fabs(double(bf.overlap - r.overlap)), 1e-6 * p.bmin) << "case " << c;
    EXPECT_LT(double(dist(bf.normal, r.normal)), 1e-6) << "case " << c;
    // geometric properties: deepest points on the surfaces, common normal
    const Spheroid si0(p.si.a, p.si.b, p.si.q), sj0(p.sj.a, p.sj.b, p.sj.q);
    EXPECT_NEAR(si0.level(r.deepest_i), 1.0, 1e-12);
    EXPECT_NEAR(sj0.level(r.deepest_j), 1.0, 1e-12);
    const Vec3 pij = r.deepest_i - (ref.d + r.deepest_j);  // P_i - P_j
    EXPECT_LT(max_abs(pij - r.overlap * r.normal), 1e-9 * p.bmin);  // ~ b |dn|
  }
  EXPECT_EQ(st.fallbacks, 0u);
  std::printf("[ random pairs ] %d cases: max |d overlap|/b = %.2e, max |d n| = %.2e, "
              "max |d c|/b = %.2e (exact construction); brute force max dev = %.2e; "
              "iterations mean %.2f max %d\n",
              cases, worst_overlap, worst_normal, worst_point, worst_bf,
              double(st.iterations) / double(st.solves), max_it);
}

TEST(SpheroidContact, NormalIsGradientOfOverlapAndMomentArmIsDeepestPoint) {
  // Envelope theorem: d(delta)/dd = -n, d(delta)/d(theta_i) = p_i x n.
  Rng rng(77);
  for (int c = 0; c < 20; ++c) {
    const RandomPair p = random_pair(rng, 1.0);
    const Vec3 d = construct(p.si, p.sj, p.n, p.delta).d;
    const SpheroidContact r = detect_spheroid_contact(p.si, p.sj, d);
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
      Vec3 e;
      e[k] = h;
      const double gp = detect_spheroid_contact(p.si, p.sj, d + e).overlap;
      const double gm = detect_spheroid_contact(p.si, p.sj, d - e).overlap;
      EXPECT_NEAR((gp - gm) / (2 * h), -r.normal[k], 1e-7);
      Vec3 axis;
      axis[k] = 1.0;
      Spheroid rp = p.si, rm = p.si;
      rp.q = axis_rotation(axis, h) * p.si.q;
      rm.q = axis_rotation(axis, -h) * p.si.q;
      const double tp = detect_spheroid_contact(rp, p.sj, d).overlap;
      const double tm = detect_spheroid_contact(rm, p.sj, d).overlap;
      EXPECT_NEAR((tp - tm) / (2 * h), cross(r.deepest_i, r.normal)[k], 1e-7);
    }
  }
}

// ---- symmetries ------------------------------------------------------------------------

TEST(SpheroidContact, SwapFlipsNormalKeepsOverlap) {
  Rng rng(99);
  for (int c = 0; c < 100; ++c) {
    const RandomPair p = random_pair(rng, 1e-3);
    const Vec3 d = construct(p.si, p.sj, p.n, p.delta).d;
    const SpheroidContact r = detect_spheroid_contact(p.si, p.sj, d);
    const SpheroidContact s = detect_spheroid_contact(p.sj, p.si, -1.0 * d);
    EXPECT_NEAR(s.overlap, r.overlap, 1e-12 * p.bmin);
    EXPECT_LT(max_abs(s.normal + r.normal), 1e-12);
    // the same contact point in space: x_i + c_r = x_j + c_s
    EXPECT_LT(max_abs(r.contact_point - (d + s.contact_point)), 1e-12 * p.bmin);
  }
}

TEST(SpheroidContact, RotatingThePairRotatesTheResult) {
  Rng rng(123);
  for (int c = 0; c < 100; ++c) {
    const RandomPair p = random_pair(rng, 1e-3);
    const Vec3 d = construct(p.si, p.sj, p.n, p.delta).d;
    const SpheroidContact r = detect_spheroid_contact(p.si, p.sj, d);
    const Quaternion g = rng.rotation();
    const Spheroid ri(p.si.a, p.si.b, g * p.si.q), rj(p.sj.a, p.sj.b, g * p.sj.q);
    const SpheroidContact s = detect_spheroid_contact(ri, rj, g.rotate(d));
    EXPECT_NEAR(s.overlap, r.overlap, 1e-12 * p.bmin);
    EXPECT_LT(max_abs(s.normal - g.rotate(r.normal)), 1e-12);
    EXPECT_LT(max_abs(s.contact_point - g.rotate(r.contact_point)), 1e-12 * p.bmin);
  }
}

TEST(SpheroidContact, EqualAxesReproduceSpheres) {
  Rng rng(7);
  for (int c = 0; c < 200; ++c) {
    const double ri = 1e-3 * rng.uniform(0.5, 1.5), rj = 1e-3 * rng.uniform(0.5, 1.5);
    const double delta = std::min(ri, rj) * std::pow(10.0, rng.uniform(-5.0, -1.0));
    const Vec3 u = rng.direction();
    const Vec3 d = (ri + rj - delta) * u;
    const Spheroid si(ri, ri, rng.rotation()), sj(rj, rj, rng.rotation());
    const SpheroidContact r = detect_spheroid_contact(si, sj, d);
    const double dist_c = norm(d);
    const double rmin = std::min(ri, rj);
    ASSERT_TRUE(r.converged);
    EXPECT_NEAR(r.overlap, ri + rj - dist_c, 1e-12 * rmin);
    EXPECT_LT(max_abs(r.normal - (1.0 / dist_c) * d), 1e-12);
    EXPECT_LT(max_abs(r.contact_point - (ri - 0.5 * (ri + rj - dist_c)) * r.normal), 1e-12 * rmin);
  }
}

TEST(SpheroidContact, PowerOfTwoLengthScalingIsExact) {
  Rng rng(31);
  for (int c = 0; c < 50; ++c) {
    const RandomPair p = random_pair(rng, 1e-3);
    const Vec3 d = construct(p.si, p.sj, p.n, p.delta).d;
    SpheroidContactCache cache0;
    const SpheroidContact r = detect_spheroid_contact(p.si, p.sj, d, &cache0);
    const SpheroidContact r2 = detect_spheroid_contact(p.si, p.sj, 1.0000001 * d, &cache0);
    for (int k : {-40, -7, 1, 5, 60}) {
      const double f = std::ldexp(1.0, k);
      const Spheroid si(f * p.si.a, f * p.si.b, p.si.q), sj(f * p.sj.a, f * p.sj.b, p.sj.q);
      SpheroidContactCache cache;
      const SpheroidContact s = detect_spheroid_contact(si, sj, f * d, &cache);
      EXPECT_EQ(s.overlap / f, r.overlap);
      EXPECT_EQ(s.normal.x, r.normal.x);
      EXPECT_EQ(s.normal.y, r.normal.y);
      EXPECT_EQ(s.normal.z, r.normal.z);
      EXPECT_EQ(s.contact_point.x / f, r.contact_point.x);
      EXPECT_EQ(s.contact_point.y / f, r.contact_point.y);
      EXPECT_EQ(s.contact_point.z / f, r.contact_point.z);
      EXPECT_EQ(s.iterations, r.iterations);
      // warm-started solve too
      const SpheroidContact s2 = detect_spheroid_contact(si, sj, f * (1.0000001 * d), &cache);
      EXPECT_EQ(s2.overlap / f, r2.overlap);
      EXPECT_EQ(s2.normal.x, r2.normal.x);
      EXPECT_EQ(s2.contact_point.z / f, r2.contact_point.z);
    }
  }
}

// ---- warm start and fallback ------------------------------------------------------------

TEST(SpheroidContact, WarmStartNeedsFewerIterations) {
  // A slowly moving pair (aspect 1.2): both bodies turn by `rate` rad per step,
  // the branch vector drifts by 1e-2 rate b per step (for the fastest rate the
  // overlap changes sign over the run: the gap side is exercised too).
  // The warm start (extrapolated from the last two normals) needs 1 Newton
  // step; cold starts need 2 here.
  for (const double rate : {1e-6, 1e-4, 1e-3}) {
    Rng rng(4242);
    const double b = 1e-3;
    Spheroid si(1.2 * b, b, rng.rotation()), sj(1.2 * b, b, rng.rotation());
    const Vec3 n0 = rng.direction();
    Vec3 d = construct(si, sj, n0, 1e-3 * b).d;
    const Vec3 ui = rng.direction(), uj = rng.direction();
    const Vec3 v = (1e-2 * rate * b) * rng.direction();
    SpheroidContactCache cache;
    SpheroidContactStats warm, cold;
    const int steps = 500;
    for (int s = 0; s < steps; ++s) {
      si.q = axis_rotation(ui, rate) * si.q;
      sj.q = axis_rotation(uj, rate) * sj.q;
      d += v;
      const SpheroidContact w = detect_spheroid_contact(si, sj, d, &cache, &warm);
      const SpheroidContact c = detect_spheroid_contact(si, sj, d, nullptr, &cold);
      ASSERT_TRUE(w.in_bounds && w.converged && c.converged);
      EXPECT_NEAR(w.overlap, c.overlap, 1e-14 * b);
      EXPECT_LT(max_abs(w.normal - c.normal), 1e-10);
    }
    EXPECT_EQ(warm.warm_starts, static_cast<std::uint64_t>(steps - 1));
    EXPECT_EQ(warm.fallbacks, 0u);
    const double it_warm = double(warm.iterations) / steps, it_cold = double(cold.iterations) / steps;
    std::printf("[ warm start ] %.0e rad per step: mean Newton steps warm %.2f, cold %.2f\n", rate,
                it_warm, it_cold);
    EXPECT_LT(it_warm, it_cold);
    EXPECT_LE(it_warm, 1.01);  // the first (cold) call included
  }
}

TEST(SpheroidContact, GivenStartValuesGiveTheSameSolveBitForBit) {
  // The pair loop computes the support values at the warm start for its
  // separation certificate and hands them to the solver (SpheroidStart):
  // the solve must be the one it would do on its own, bit for bit, and the
  // certificate g(start) must bound the overlap from above.
  Rng rng(9090);
  const double b = 1e-3;
  Spheroid si(1.2 * b, b, rng.rotation()), sj(1.2 * b, b, rng.rotation());
  Vec3 d = construct(si, sj, rng.direction(), 1e-3 * b).d;
  const Vec3 ui = rng.direction(), uj = rng.direction(), v = (1e-6 * b) * rng.direction();
  SpheroidContactCache plain, given;
  int warm = 0;
  for (int s = 0; s < 300; ++s) {
    si.q = axis_rotation(ui, 1e-4) * si.q;
    sj.q = axis_rotation(uj, 1e-4) * sj.q;
    d += v;
    const SpheroidSupport bi = SpheroidSupport::of(si), bj = SpheroidSupport::of(sj);
    const SpheroidContact a = detect_spheroid_contact(bi, bj, d, &plain);
    SpheroidContact c;
    if (given.valid) {
      ++warm;
      const SpheroidStart start = SpheroidStart::at(bi, bj, warm_start_normal(given));
      EXPECT_GE(start.gap(d), a.overlap - 1e-12 * b);  // min g <= g(n), to rounding
      c = detect_spheroid_contact(bi, bj, d, &given, nullptr, {}, &start);
    } else {
      c = detect_spheroid_contact(bi, bj, d, &given);
    }
    ASSERT_TRUE(a.converged);
    EXPECT_EQ(a.overlap, c.overlap);
    EXPECT_EQ(a.normal.x, c.normal.x);
    EXPECT_EQ(a.normal.y, c.normal.y);
    EXPECT_EQ(a.normal.z, c.normal.z);
    EXPECT_EQ(a.contact_point.x, c.contact_point.x);
    EXPECT_EQ(a.contact_point.z, c.contact_point.z);
  }
  EXPECT_EQ(warm, 299);
}

TEST(SpheroidContact, BadWarmStartTakesFallbackAndStillGetsTheAnswer) {
  Rng rng(555);
  SpheroidContactStats st;
  for (int c = 0; c < 50; ++c) {
    const RandomPair p = random_pair(rng, 1e-3);
    const Constructed ref = construct(p.si, p.sj, p.n, p.delta);
    for (int kind = 0; kind < 2; ++kind) {
      SpheroidContactCache cache;
      cache.valid = true;
      // reversed normal, or a normal perpendicular to the true one
      cache.normal = kind == 0 ? -1.0 * p.n : normalized_perp(p.n);
      const std::uint64_t before = st.fallbacks;
      const SpheroidContact r = detect_spheroid_contact(p.si, p.sj, ref.d, &cache, &st);
      ASSERT_TRUE(r.converged);
      if (kind == 0) {
        EXPECT_TRUE(r.fallback);
        EXPECT_EQ(st.fallbacks, before + 1);
      }
      EXPECT_LT(std::fabs(double(r.overlap - ref.overlap)), 1e-10 * p.bmin);
      EXPECT_LT(double(dist(ref.normal, r.normal)), 1e-9);
      EXPECT_TRUE(cache.valid);
      EXPECT_LT(max_abs(cache.normal - r.normal), 1e-15);
    }
  }
  EXPECT_GE(st.fallbacks, 50u);
  EXPECT_EQ(st.failures, 0u);
  std::printf("[ fallback ] %llu fallbacks in %llu solves, mean steps %.2f\n",
              (unsigned long long)st.fallbacks, (unsigned long long)st.solves,
              double(st.iterations) / double(st.solves));
}

TEST(SpheroidContact, ForcedFallbackAndReportedFailure) {
  const double b = 1e-3;
  Rng rng(8);
  const RandomPair p = random_pair(rng, b);
  const Constructed ref = construct(p.si, p.sj, p.n, p.delta);
  // plain Newton allowed a single step: cannot converge from a cold start
  SpheroidContactOptions opt;
  opt.max_iterations = 1;
  SpheroidContactStats st;
  SpheroidContactCache cache;
  const SpheroidContact r = detect_spheroid_contact(p.si, p.sj, ref.d, &cache, &st, opt);
  EXPECT_TRUE(r.fallback);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(st.fallbacks, 1u);
  EXPECT_LT(std::fabs(double(r.overlap - ref.overlap)), 1e-10 * p.bmin);
  // no iterations left anywhere (and a reversed warm start): converged =
  // false, counted, cache invalidated
  opt.max_fallback_iterations = 1;
  cache.normal = -1.0 * cache.normal;
  const SpheroidContact f = detect_spheroid_contact(p.si, p.sj, ref.d, &cache, &st, opt);
  EXPECT_FALSE(f.converged);
  EXPECT_EQ(st.failures, 1u);
  EXPECT_FALSE(cache.valid);
}

// ---- cost -------------------------------------------------------------------------------

TEST(SpheroidContact, CostPerCall) {
  Rng rng(1);
  const int n = 256;
  std::vector<RandomPair> pairs;
  std::vector<Vec3> ds;
  for (int c = 0; c < n; ++c) pairs.push_back(random_pair(rng, 1e-3));
  for (const RandomPair& p : pairs) ds.push_back(construct(p.si, p.sj, p.n, p.delta).d);
  std::vector<SpheroidContactCache> caches(n);
  volatile double sink = 0;
  auto time_ns = [&](auto&& body, int reps) {
    // thread CPU time: the machine may be shared, wall time would count waits
    timespec t0, t1;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
    for (int r = 0; r < reps; ++r)
      for (int c = 0; c < n; ++c) sink = sink + body(c);
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
    return (1e9 * double(t1.tv_sec - t0.tv_sec) + double(t1.tv_nsec - t0.tv_nsec)) / (double(reps) * n);
  };
  const int reps = 200;
  const double cold = time_ns([&](int c) {
    return detect_spheroid_contact(pairs[c].si, pairs[c].sj, ds[c]).overlap;
  }, reps);
  for (int c = 0; c < n; ++c) detect_spheroid_contact(pairs[c].si, pairs[c].sj, ds[c], &caches[c]);
  // warm: the pair moved by 1e-6 b since the cached solution
  const double warm = time_ns([&](int c) {
    SpheroidContactCache k = caches[c];
    return detect_spheroid_contact(pairs[c].si, pairs[c].sj, ds[c] + Vec3{1e-9, 0, 0}, &k).overlap;
  }, reps);
  const double reject = time_ns([&](int c) {
    return detect_spheroid_contact(pairs[c].si, pairs[c].sj, 10.0 * ds[c]).iterations;
  }, reps);
  std::printf("[ cost ] ns per call on one core: cold %.0f, warm %.0f, bounding reject %.1f\n", cold,
              warm, reject);
  EXPECT_TRUE(std::isfinite(sink));  // timings are reported, not asserted (shared machines)
}
