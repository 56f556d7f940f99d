// Spheroid geometry and spheroid-spheroid contact detection (spheroid.h,
// spheroid_contact.h) against closed forms, an independent brute-force
// long-double reference (support/spheroid_reference.h), symmetry and
// scaling properties. The solver's warm start, fallback and cost:
// test_spheroid_contact_solver.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "virtual_triaxial/dem/spheroid.h"
#include "virtual_triaxial/dem/spheroid_contact.h"
#include "support/spheroid_reference.h"

using namespace vt::dem;
using namespace vt::test;


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
