// Numerical failure is detected, never silently carried on: a dense lattice
// run with c_t raised until it blows up stops with a failure reason within a
// few hundred steps of the blow-up, while the run below the threshold stays
// stable and conserves energy.
#include <gtest/gtest.h>

#include <cmath>

#include "support/scenes.h"
#include "virtual_triaxial/dem/random_stream.h"

using namespace vt::dem;

namespace {

Simulation dense_lattice(double ct) {
  const int n = 5;
  const double r = 1e-3, a = 2 * r * (1 - 0.01);
  PeriodicCell cell(Vec3{n * a, n * a, n * a});
  Particles p;
  RandomStream rng(3);
  int id = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i, ++id)
        p.add_sphere(id, r, 2650, {(i + 0.5) / n, (j + 0.5) / n, (k + 0.5) / n},
                     {1e-3 * rng.uniform(-1, 1), 1e-3 * rng.uniform(-1, 1), 1e-3 * rng.uniform(-1, 1)});
  return Simulation(std::move(p), cell, vt::test::undamped(ct, 0.5));
}

}  // namespace

TEST(StabilityDetection, RaisingTheTimeStepUntilBlowUpIsDetectedPromptly) {
  double stable_ct = 0, unstable_ct = 0;
  for (double ct = 0.3; ct < 5000 && unstable_ct == 0; ct *= 2) {
    Simulation sim = dense_lattice(ct);
    ASSERT_TRUE(sim.step(true));
    const double e0 = sim.measures().energy.kinetic() + sim.measures().energy.elastic;
    std::int64_t blow_up = -1;
    for (int k = 1; k < 3000; ++k) {
      if (!sim.step(true)) break;
      const Measures m = sim.measures();
      if (blow_up < 0 && m.energy.kinetic() + m.energy.elastic > 2 * e0) blow_up = m.step;
    }
    if (!sim.unstable()) {
      EXPECT_LT(blow_up, 0) << "energy doubled at c_t = " << ct << " without detection";
      stable_ct = ct;
      continue;
    }
    unstable_ct = ct;
    EXPECT_FALSE(sim.failure().empty());
    // Detected no later than a few hundred steps after the energy doubled.
    const std::int64_t detected = sim.steps();
    if (blow_up >= 0) {
      EXPECT_LE(detected - blow_up, 300) << sim.failure();
    }
    EXPECT_LT(detected, 3000);
  }
  EXPECT_GE(stable_ct, 0.3) << "c_t = 0.3 must be stable";
  EXPECT_GT(unstable_ct, 0.0) << "no c_t up to 5000 blew up";
  std::printf("stable up to c_t = %g, unstable at c_t = %g\n", stable_ct, unstable_ct);
}
