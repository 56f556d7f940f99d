// The warm one-step spheroid solve in lanes (spheroid_warm_lanes.h) against
// the scalar common-normal solver (spheroid_contact.h): the same overlap,
// normal and contact point to rounding on moving pairs, the separation
// certificate for pairs apart, the hand-back of every case one step cannot
// settle, and lane results that do not depend on the other lanes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include "virtual_triaxial/dem/spheroid.h"
#include "virtual_triaxial/dem/spheroid_contact.h"
#include "virtual_triaxial/dem/spheroid_warm_lanes.h"

using namespace vt::dem;

namespace {

constexpr int kLanes = SpheroidWarmLanes::kLanes;
constexpr double kTolerance = SpheroidContactOptions{}.step_tolerance;

struct Rng {
  std::mt19937_64 g;
  explicit Rng(std::uint64_t seed) : g(seed) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * static_cast<double>(g() >> 11) * 0x1.0p-53; }
  Vec3 direction() {
    const double z = uniform(-1.0, 1.0), phi = uniform(0.0, 2.0 * M_PI);
    const double r = std::sqrt(1.0 - z * z);
    return {r * std::cos(phi), r * std::sin(phi), z};
  }
  Quaternion rotation() {
    const Vec3 u = direction();
    const double phi = uniform(0.0, 2.0 * M_PI), s = std::sin(0.5 * phi);
    return {std::cos(0.5 * phi), s * u.x, s * u.y, s * u.z};
  }
};

Quaternion turn(const Vec3& u, double phi) {
  const double s = std::sin(0.5 * phi);
  return {std::cos(0.5 * phi), s * u.x, s * u.y, s * u.z};
}

double max_abs(const Vec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

/// A pair whose centre line is along dhat, placed by the scalar solver so the
/// overlap is `overlap` (> 0 contact, < 0 gap) [m].
struct Pair {
  Spheroid si, sj;
  Vec3 d;
};
Pair place(Rng& rng, double b, double aspect_i, double aspect_j, double overlap) {
  Pair p{Spheroid(aspect_i * b, b, rng.rotation()), Spheroid(aspect_j * b, b, rng.rotation()), {}};
  const Vec3 dhat = rng.direction();
  double dist = 0.5 * (p.si.a + p.si.b + p.sj.a + p.sj.b);
  for (int it = 0; it < 30; ++it) {
    const SpheroidContact sc = detect_spheroid_contact(p.si, p.sj, dist * dhat);
    dist += (sc.overlap - overlap) / dot(sc.normal, dhat);
  }
  p.d = dist * dhat;
  return p;
}

/// A valid cache whose last normal is the converged normal of the pair.
SpheroidContactCache solved_cache(const Pair& p) {
  SpheroidContactCache cache;
  detect_spheroid_contact(p.si, p.sj, p.d, &cache);
  EXPECT_TRUE(cache.valid);
  return cache;
}

void expect_same_lane(const SpheroidWarmLanes& a, int ka, const SpheroidWarmLanes& b, int kb) {
  EXPECT_EQ(a.code[ka], b.code[kb]);
  EXPECT_EQ(a.gap[ka], b.gap[kb]);
  EXPECT_EQ(a.delta[ka], b.delta[kb]);
  EXPECT_EQ(a.ox[ka], b.ox[kb]);
  EXPECT_EQ(a.oy[ka], b.oy[kb]);
  EXPECT_EQ(a.oz[ka], b.oz[kb]);
  EXPECT_EQ(a.cx[ka], b.cx[kb]);
  EXPECT_EQ(a.cy[ka], b.cy[kb]);
  EXPECT_EQ(a.cz[ka], b.cz[kb]);
}

}  // namespace

TEST(SpheroidWarmLanes, MovingPairsMatchTheScalarSolver) {
  // A pair per lane, of aspect 1 to 2 (b from 0.5 to 2 mm) overlapping by
  // 3e-2 b (enough for all to stay in contact), each body turning by 1e-4
  // rad per step and the centres drifting by 1e-6 b: from
  // warm caches (extrapolated start) every lane settles in one step, with the overlap,
  // normal and contact point of detect_spheroid_contact to rounding (its
  // Newton step error is ~1e-10 rad, so the overlap agrees to ~b 1e-20 and
  // the rest to a few ulp), while both follow their own caches.
  Rng rng(2026);
  Pair pairs[kLanes];
  Vec3 spin_i[kLanes], spin_j[kLanes], drift[kLanes];
  SpheroidContactCache scalar_cache[kLanes], lane_cache[kLanes];
  double b[kLanes];
  for (int k = 0; k < kLanes; ++k) {
    b[k] = 1e-3 * std::pow(2.0, rng.uniform(-1.0, 1.0));
    const double s = static_cast<double>(k) / (kLanes - 1);
    pairs[k] = place(rng, b[k], 1.0 + s, 2.0 - s, 3e-2 * b[k]);
    spin_i[k] = rng.direction();
    spin_j[k] = rng.direction();
    drift[k] = (1e-6 * b[k]) * rng.direction();
  }
  // Both caches start from two scalar solves one step apart (the warm start
  // extrapolates from the last two normals).
  const auto advance = [&](int k) {
    Pair& p = pairs[k];
    p.si.q = turn(spin_i[k], 1e-4) * p.si.q;
    p.sj.q = turn(spin_j[k], 1e-4) * p.sj.q;
    p.d += drift[k];
  };
  for (int k = 0; k < kLanes; ++k) {
    detect_spheroid_contact(pairs[k].si, pairs[k].sj, pairs[k].d, &scalar_cache[k]);
    advance(k);
    detect_spheroid_contact(pairs[k].si, pairs[k].sj, pairs[k].d, &scalar_cache[k]);
    ASSERT_TRUE(scalar_cache[k].has_previous);
    lane_cache[k] = scalar_cache[k];
  }
  SpheroidWarmLanes lanes;
  int solved = 0;
  for (int step = 0; step < 200; ++step) {
    for (int k = 0; k < kLanes; ++k) {
      advance(k);
      const Pair& p = pairs[k];
      lanes.set(k, SpheroidSupport::of(p.si), SpheroidSupport::of(p.sj), p.d, lane_cache[k]);
    }
    solve_spheroid_warm_lanes(lanes, kTolerance);
    for (int k = 0; k < kLanes; ++k) {
      const Pair& p = pairs[k];
      const SpheroidContact sc = detect_spheroid_contact(p.si, p.sj, p.d, &scalar_cache[k]);
      ASSERT_TRUE(sc.converged);
      ASSERT_EQ(lanes.outcome(k), WarmOutcome::Solved) << "lane " << k << " step " << step;
      ++solved;
      EXPECT_NEAR(lanes.delta[k], sc.overlap, 1e-14 * b[k]);
      EXPECT_LT(max_abs(lanes.normal(k) - sc.normal), 1e-13);
      EXPECT_LT(max_abs(lanes.contact_point(k) - sc.contact_point), 1e-14 * b[k]);
      ASSERT_GT(lanes.delta[k], 0.0);
      advance_cache(lane_cache[k], lanes.normal(k));
      EXPECT_TRUE(lane_cache[k].has_previous);
      EXPECT_LT(max_abs(lane_cache[k].previous - scalar_cache[k].previous), 1e-13);
    }
  }
  EXPECT_EQ(solved, 200 * kLanes);
}

TEST(SpheroidWarmLanes, PairsApartCarryTheSeparationCertificate) {
  // A pair found in contact, then moved apart along its normal by 1e-2 b: the
  // lane proves it apart at the warm start without a Newton step, with the
  // gap -g(n0) > 0 of the scalar certificate.
  Rng rng(77);
  const double b = 1e-3;
  for (int k = 0; k < kLanes; ++k) {
    Pair p = place(rng, b, 1.2, 1.5, 1e-4 * b);
    const SpheroidContactCache cache = solved_cache(p);
    p.d += (1e-2 * b) * cache.normal;
    SpheroidWarmLanes lanes;
    lanes.set(0, SpheroidSupport::of(p.si), SpheroidSupport::of(p.sj), p.d, cache);
    for (int l = 1; l < kLanes; ++l) lanes.repeat(0, l);
    solve_spheroid_warm_lanes(lanes, kTolerance);
    const SpheroidSupport si = SpheroidSupport::of(p.si), sj = SpheroidSupport::of(p.sj);
    const double g = spheroid_gap_bound(si, sj, p.d, warm_start_normal(cache));
    ASSERT_EQ(lanes.outcome(0), WarmOutcome::Apart);
    EXPECT_GT(lanes.gap[0], 0.9e-2 * b);
    EXPECT_NEAR(lanes.gap[0], -g, 1e-15 * b);
    // the solver agrees: apart by at least the certificate's gap
    EXPECT_LE(detect_spheroid_contact(p.si, p.sj, p.d).overlap, -lanes.gap[0] + 1e-15 * b);
  }
}

TEST(SpheroidWarmLanes, WhatOneStepCannotSettleGoesToTheScalarSolver) {
  // A stale warm start (the cache's normal 0.05 rad off: the Newton step is
  // far above the 1e-5 rad tolerance) and a start not within 1e-6 of unit
  // length are handed back (Scalar); the scalar solver still converges on
  // the first. The same pair with a fresh cache settles in the lanes.
  Rng rng(5);
  const double b = 1e-3;
  const Pair p = place(rng, b, 1.3, 1.1, 2e-3 * b);
  const SpheroidContactCache fresh = solved_cache(p);
  SpheroidContactCache stale = fresh, long_normal = fresh;
  const Vec3 off = cross(fresh.normal, rng.direction());
  stale.normal = turn((1.0 / norm(off)) * off, 0.05).rotate(fresh.normal);
  stale.has_previous = false;
  long_normal.normal = 1.01 * fresh.normal;
  long_normal.has_previous = false;
  SpheroidWarmLanes lanes;
  const SpheroidSupport si = SpheroidSupport::of(p.si), sj = SpheroidSupport::of(p.sj);
  lanes.set(0, si, sj, p.d, stale);
  lanes.set(1, si, sj, p.d, long_normal);
  for (int k = 2; k < kLanes; ++k) lanes.set(k, si, sj, p.d, fresh);
  solve_spheroid_warm_lanes(lanes, kTolerance);
  EXPECT_EQ(lanes.outcome(0), WarmOutcome::Scalar);
  EXPECT_EQ(lanes.outcome(1), WarmOutcome::Scalar);
  for (int k = 2; k < kLanes; ++k) {
    EXPECT_EQ(lanes.outcome(k), WarmOutcome::Solved);
    EXPECT_NEAR(lanes.delta[k], 2e-3 * b, 1e-14 * b);
  }
  SpheroidContactCache c = stale;
  const SpheroidContact sc = detect_spheroid_contact(si, sj, p.d, &c);
  EXPECT_TRUE(sc.converged);
  EXPECT_GT(sc.iterations, 1);
  EXPECT_NEAR(sc.overlap, 2e-3 * b, 1e-14 * b);
}

TEST(SpheroidWarmLanes, StartsOffUnitLengthMaximaAndFarPairsGoToTheScalarSolver) {
  const double b = 1e-3, a = 1.5 * b;
  const SpheroidSupport si = SpheroidSupport::of(Spheroid(a, b)), sj = SpheroidSupport::of(Spheroid(a, b));
  SpheroidWarmLanes lanes;
  // 0: a pair in contact whose cached normal has |n|^2 = 1 + 2e-6: one step
  // for 1/|v| leaves it within 1e-6 of unit length afterwards, so only the
  // start's own test can hand it back.
  Rng rng(8);
  const Pair p = place(rng, b, 1.2, 1.4, 1e-3 * b);
  SpheroidContactCache off_unit = solved_cache(p);
  off_unit.normal = std::sqrt(1.0 + 2e-6) * off_unit.normal;
  off_unit.has_previous = false;
  lanes.set(0, SpheroidSupport::of(p.si), SpheroidSupport::of(p.sj), p.d, off_unit);
  // 1: coincident aligned spheroids, started along their axes: g is at a
  // maximum there (gradient 0, H = 2 b^2/a - 2a < 0): one "converged" step
  // would report delta = 2a instead of the true 2b.
  SpheroidContactCache along_axis;
  along_axis.normal = {1.0, 0.0, 0.0};
  along_axis.valid = true;
  lanes.set(1, si, sj, Vec3{}, along_axis);
  // 2: centres 1.01 (a_i + a_j) apart, started across the centre line
  // (g > 0 there, no certificate): bounding spheres apart.
  SpheroidContactCache across;
  across.normal = {0.0, 1.0, 0.0};
  across.valid = true;
  const Vec3 far{2.02 * a, 0.0, 0.0};
  lanes.set(2, si, sj, far, across);
  for (int k = 3; k < kLanes; ++k) lanes.repeat(0, k);
  solve_spheroid_warm_lanes(lanes, kTolerance);
  EXPECT_EQ(lanes.outcome(0), WarmOutcome::Scalar);
  EXPECT_EQ(lanes.outcome(1), WarmOutcome::Scalar);
  EXPECT_EQ(lanes.outcome(2), WarmOutcome::Scalar);
  // what the scalar solver then finds
  SpheroidContactCache c0 = off_unit, c1 = along_axis, c2 = across;
  EXPECT_NEAR(detect_spheroid_contact(SpheroidSupport::of(p.si), SpheroidSupport::of(p.sj), p.d, &c0).overlap,
              1e-3 * b, 1e-14 * b);
  EXPECT_NEAR(detect_spheroid_contact(si, sj, Vec3{}, &c1).overlap, 2.0 * b, 1e-14 * b);
  EXPECT_LT(detect_spheroid_contact(si, sj, far, &c2).overlap, 0.0);
  // the same start at unit length settles in the lanes
  SpheroidContactCache unit = off_unit;
  unit.normal = (1.0 / norm(unit.normal)) * unit.normal;
  lanes.set(0, SpheroidSupport::of(p.si), SpheroidSupport::of(p.sj), p.d, unit);
  solve_spheroid_warm_lanes(lanes, kTolerance);
  EXPECT_EQ(lanes.outcome(0), WarmOutcome::Solved);
}

TEST(SpheroidWarmLanes, ALaneResultDoesNotDependOnTheOtherLanes) {
  // The same pair in lane 0 among pairs in contact and in lane 5 (the first
  // SIMD register) and the last lane (the last register) among copies of a
  // pair apart: the same bits (so a pair's result does not depend on which
  // group, chunk, lane or thread takes it).
  Rng rng(31);
  const double b = 1e-3;
  const Pair target = place(rng, b, 1.2, 1.2, 5e-4 * b);
  const SpheroidContactCache target_cache = solved_cache(target);
  const SpheroidSupport ti = SpheroidSupport::of(target.si), tj = SpheroidSupport::of(target.sj);
  SpheroidWarmLanes a, c;
  a.set(0, ti, tj, target.d, target_cache);
  for (int k = 1; k < kLanes; ++k) {
    const Pair other = place(rng, b, 1.5, 1.1, 1e-3 * b);
    a.set(k, SpheroidSupport::of(other.si), SpheroidSupport::of(other.sj), other.d, solved_cache(other));
  }
  Pair apart = place(rng, b, 1.1, 1.4, 1e-4 * b);
  const SpheroidContactCache apart_cache = solved_cache(apart);
  apart.d += (0.1 * b) * apart_cache.normal;
  c.set(0, SpheroidSupport::of(apart.si), SpheroidSupport::of(apart.sj), apart.d, apart_cache);
  for (int k = 1; k < kLanes; ++k) c.repeat(0, k);
  c.set(5, ti, tj, target.d, target_cache);
  c.set(kLanes - 1, ti, tj, target.d, target_cache);
  solve_spheroid_warm_lanes(a, kTolerance);
  solve_spheroid_warm_lanes(c, kTolerance);
  EXPECT_EQ(a.outcome(0), WarmOutcome::Solved);
  EXPECT_EQ(c.outcome(0), WarmOutcome::Apart);
  expect_same_lane(a, 0, c, 5);
  expect_same_lane(a, 0, c, kLanes - 1);
}
