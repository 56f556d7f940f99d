// Undamped frictionless dense gas in a periodic cell: total energy is
// conserved by the leapfrog scheme, with no secular growth, and the error
// falls with the time-step ratio c_t.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "support/scenes.h"
#include "virtual_triaxial/dem/simulation.h"

using namespace vt::dem;

namespace {

struct EnergyRun {
  double max_rel_error = 0;     ///< max |E - E0| / E0
  double drift_per_half = 0;    ///< mean error, second half minus first half, / E0
  std::int64_t contacts_seen = 0;
};

EnergyRun run_gas(double ct, double physical_time_in_t0) {
  vt::test::CloudScene sc = vt::test::polydisperse_cloud(120, 1.6, 3);
  vt::test::randomize_velocities(sc.particles, 10.0, 2000.0, 11);
  SimulationSettings s = vt::test::undamped(ct, 0.0);
  s.check_interval = 1000000;
  Simulation sim(std::move(sc.particles), sc.cell, s);
  const std::int64_t steps = static_cast<std::int64_t>(physical_time_in_t0 / ct);
  const std::int64_t every = 50;
  EnergyRun r;
  double e0 = -1;
  std::vector<double> errors;
  for (std::int64_t k = 0; k < steps; ++k) {
    const bool meas = k % every == 0;
    EXPECT_TRUE(sim.step(meas)) << sim.failure();
    if (!meas) continue;
    const Measures m = sim.measures();
    const double e = m.energy.kinetic() + m.energy.elastic;
    if (e0 < 0) e0 = e;
    const double err = (e - e0) / e0;
    errors.push_back(err);
    r.max_rel_error = std::max(r.max_rel_error, std::fabs(err));
    r.contacts_seen += m.contacts;
  }
  const std::size_t h = errors.size() / 2;
  double a = 0, b = 0;
  for (std::size_t i = 0; i < h; ++i) a += errors[i];
  for (std::size_t i = h; i < 2 * h; ++i) b += errors[i];
  r.drift_per_half = (b - a) / static_cast<double>(h);
  return r;
}

}  // namespace

TEST(EnergyConservation, FrictionlessGasConservesEnergyAndErrorFallsWithTimeStep) {
  const double duration = 1e5 * 0.1;  // 1e5 steps at c_t = 0.1, in units of T0
  const EnergyRun coarse = run_gas(0.1, duration);
  const EnergyRun fine = run_gas(0.05, duration);
  EXPECT_GT(coarse.contacts_seen, 1000) << "the gas must collide";
  EXPECT_LT(coarse.max_rel_error, 1e-3);
  EXPECT_LT(std::fabs(coarse.drift_per_half), 0.25e-3) << "secular drift";
  EXPECT_LT(fine.max_rel_error, coarse.max_rel_error) << "error must fall with c_t";
  RecordProperty("max_rel_error_ct_0.1", std::to_string(coarse.max_rel_error));
  RecordProperty("max_rel_error_ct_0.05", std::to_string(fine.max_rel_error));
  std::printf("energy error: c_t=0.1 max %.3g drift %.3g; c_t=0.05 max %.3g drift %.3g\n",
              coarse.max_rel_error, coarse.drift_per_half, fine.max_rel_error, fine.drift_per_half);
}
