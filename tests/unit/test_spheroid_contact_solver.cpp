// The spheroid contact solver (spheroid_contact.h): warm starts, given start
// values, the fallback and reported failures, against the exact inverse
// construction of support/spheroid_reference.h; and its cost per call
// (reported, not asserted). Geometry and accuracy: test_spheroid_contact.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "virtual_triaxial/dem/spheroid.h"
#include "virtual_triaxial/dem/spheroid_contact.h"
#include "support/spheroid_reference.h"

using namespace vt::dem;
using namespace vt::test;


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
