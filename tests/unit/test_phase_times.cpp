// PhaseTimes (dem/phase_times.h): where a step's time goes per thread.
//   - the arithmetic: busy = sum of the phases, waits = both regions less
//     busy, reset zeroes everything, a thread without a slot reads 0; the
//     waits split step by step into imbalance (its steady part from the
//     totals) and overhead, against hand sums;
//   - on spatially sorted sphere and spheroid packings stepped by Simulation
//     on one and on two threads: every thread of the team times its own pair
//     loop and its integration (> 0), on two threads its preparation (its
//     sums zeroed) too, no thread's phases exceed the regions that hold them
//     (waits >= 0: the regions are timed around the team, the phases inside
//     it, with the same clock), the team's mean waits are imbalance +
//     overhead, and reset_phase_times() starts from zero.
#include <gtest/gtest.h>

#include <omp.h>

#include <string>

#include "support/omp_threads.h"
#include "support/scenes.h"
#include "support/spheroid_scenes.h"
#include "virtual_triaxial/dem/periodic_tiling.h"
#include "virtual_triaxial/dem/phase_times.h"
#include "virtual_triaxial/dem/simulation.h"

using namespace vt::dem;

TEST(PhaseTimes, BusyIsTheSumOfThePhasesAndWaitsTheRegionsLessBusy) {
  PhaseTimes pt;
  pt.ensure_threads(2);
  EXPECT_EQ(pt.threads(), 2);
  pt.add(0, PhaseTimes::Pairs, 1.5);
  pt.add(0, PhaseTimes::Integrate, 0.25);
  pt.add(0, PhaseTimes::Pairs, 0.5);
  pt.add(1, PhaseTimes::Prepare, 0.125);
  pt.add_region(PhaseTimes::ForceRegion, 2.5);
  pt.add_region(PhaseTimes::IntegrationRegion, 0.5);
  EXPECT_EQ(pt.seconds(0, PhaseTimes::Pairs), 2.0);
  EXPECT_EQ(pt.busy(0), 2.25);
  EXPECT_EQ(pt.busy(1), 0.125);
  EXPECT_EQ(pt.waits(0), 0.75);
  EXPECT_EQ(pt.waits(1), 2.875);
  EXPECT_EQ(pt.seconds(2, PhaseTimes::Pairs), 0.0) << "no slot";
  EXPECT_EQ(pt.seconds(-1, PhaseTimes::Pairs), 0.0) << "no slot";
  pt.ensure_threads(1);  // never shrinks
  EXPECT_EQ(pt.threads(), 2);
  pt.reset();
  EXPECT_EQ(pt.busy(0), 0.0);
  EXPECT_EQ(pt.region(PhaseTimes::ForceRegion), 0.0);
  EXPECT_EQ(pt.threads(), 2);
  EXPECT_STREQ(PhaseTimes::name(PhaseTimes::Prepare), "prepare");
  EXPECT_STREQ(PhaseTimes::name(PhaseTimes::Integrate), "integrate");
}

TEST(PhaseTimes, WaitsSplitIntoImbalanceSteadyPartAndOverhead) {
  PhaseTimes pt;
  pt.ensure_threads(3);  // thread 2 never in a team
  // force region, step 1: thread 0 busy 3, thread 1 busy 1, wall 3.5
  pt.add(0, PhaseTimes::Pairs, 2.0);
  pt.add(0, PhaseTimes::Prepare, 1.0);
  pt.add(1, PhaseTimes::Pairs, 1.0);
  pt.add_region(PhaseTimes::ForceRegion, 3.5);
  // integration, step 1: 0.5 and 0.5, wall 0.75
  pt.add(0, PhaseTimes::Integrate, 0.5);
  pt.add(1, PhaseTimes::Integrate, 0.5);
  pt.add_region(PhaseTimes::IntegrationRegion, 0.75);
  // force region, step 2: thread 0 busy 1, thread 1 busy 4, wall 4.25
  pt.add(0, PhaseTimes::Pairs, 1.0);
  pt.add(1, PhaseTimes::Pairs, 4.0);
  pt.add_region(PhaseTimes::ForceRegion, 4.25);
  // force: sum of (max - mean) = (3 - 2) + (4 - 2.5); totals 4 and 5
  EXPECT_DOUBLE_EQ(pt.imbalance(PhaseTimes::ForceRegion), 2.5);
  EXPECT_DOUBLE_EQ(pt.steady_imbalance(PhaseTimes::ForceRegion), 0.5);
  EXPECT_DOUBLE_EQ(pt.overhead(PhaseTimes::ForceRegion), 0.5 + 0.25);
  EXPECT_DOUBLE_EQ(pt.imbalance(PhaseTimes::IntegrationRegion), 0.0);
  EXPECT_DOUBLE_EQ(pt.overhead(PhaseTimes::IntegrationRegion), 0.25);
  // the team's mean waits are imbalance + overhead over both regions
  const double mean_waits = 0.5 * (pt.waits(0) + pt.waits(1));
  EXPECT_DOUBLE_EQ(mean_waits, pt.imbalance(PhaseTimes::ForceRegion) + pt.overhead(PhaseTimes::ForceRegion) +
                                   pt.imbalance(PhaseTimes::IntegrationRegion) +
                                   pt.overhead(PhaseTimes::IntegrationRegion));
  // one thread: no imbalance, overhead = wall - busy
  pt.reset();
  pt.add(0, PhaseTimes::Pairs, 1.0);
  pt.add_region(PhaseTimes::ForceRegion, 1.25);
  EXPECT_EQ(pt.imbalance(PhaseTimes::ForceRegion), 0.0);
  EXPECT_EQ(pt.steady_imbalance(PhaseTimes::ForceRegion), 0.0);
  EXPECT_EQ(pt.overhead(PhaseTimes::ForceRegion), 0.25);
}

namespace {

using vt::test::RestoreThreads;

/// Steps `start` 5 steps on one thread, 5 on `threads` (the team's plan is
/// made), resets the timers and steps 20 more; checks the invariants of
/// the phase times of those 20 steps.
void check_steps_on(const SimulationState& start, int threads) {
  RestoreThreads restore;
  omp_set_num_threads(1);
  Simulation sim(start);
  ASSERT_EQ(sim.run(5), 5) << sim.failure();
  omp_set_num_threads(threads);
  ASSERT_EQ(sim.run(5), 5) << sim.failure();
  sim.reset_phase_times();
  const PhaseTimes& pt = sim.phase_times();
  EXPECT_EQ(pt.busy(0), 0.0);
  EXPECT_EQ(pt.region(PhaseTimes::ForceRegion), 0.0);
  ASSERT_EQ(sim.run(20), 20) << sim.failure();
  ASSERT_GE(pt.threads(), threads);
  EXPECT_GT(pt.region(PhaseTimes::ForceRegion), 0.0);
  EXPECT_GT(pt.region(PhaseTimes::IntegrationRegion), 0.0);
  for (int t = 0; t < threads; ++t) {
    const std::string at = std::to_string(threads) + " threads, thread " + std::to_string(t);
    EXPECT_GT(pt.seconds(t, PhaseTimes::Pairs), 0.0) << at;
    EXPECT_GT(pt.seconds(t, PhaseTimes::Integrate), 0.0) << at;
    EXPECT_GE(pt.waits(t), 0.0) << at << ": phases outside their regions";
    EXPECT_LE(pt.seconds(t, PhaseTimes::Integrate), pt.region(PhaseTimes::IntegrationRegion)) << at;
    // every thread zeroes its own sums (one thread: all of them)
    EXPECT_GT(pt.seconds(t, PhaseTimes::Prepare), 0.0) << at;
  }
  // the team's mean waits split into imbalance and overhead, step by step
  double mean_waits = 0.0, split = 0.0;
  for (int t = 0; t < threads; ++t) mean_waits += pt.waits(t) / threads;
  for (const auto r : {PhaseTimes::ForceRegion, PhaseTimes::IntegrationRegion}) {
    // equal when one thread is the slowest in every step: round-off decides
    EXPECT_GE(pt.imbalance(r) + 1e-12, pt.steady_imbalance(r));
    EXPECT_GE(pt.steady_imbalance(r), 0.0);
    EXPECT_GE(pt.overhead(r), 0.0);
    split += pt.imbalance(r) + pt.overhead(r);
  }
  EXPECT_NEAR(mean_waits, split, 1e-9) << threads << " threads";
  EXPECT_EQ(sim.split_used(), threads > 1);
  if (threads > 1) {
    EXPECT_GT(sim.ghost_pairs(), 0u) << "pairs crossing the runs, evaluated again as ghosts";
  }
}

}  // namespace

TEST(PhaseTimes, EveryThreadTimesItsPairLoopAndIntegrationInsideTheRegions) {
  // 1600 spheres, sorted in space: 4 chunks, pairs crossing two threads' runs
  const SimulationState spheres = vt::test::spatially_sorted(vt::test::loaded_packing(1600));
  check_steps_on(spheres, 1);
  check_steps_on(spheres, 2);
}

TEST(PhaseTimes, SpheroidThreadsTimeTheirPairLoopsAndGhosts) {
  // 2 x 2 x 2 tiles of 300 loaded spheroids, sorted: 2400 in 5 chunks
  const SimulationState spheroids =
      vt::test::spatially_sorted(tile_periodic(vt::test::loaded_spheroid_packing(), 2, 2, 2));
  check_steps_on(spheroids, 1);
  check_steps_on(spheroids, 2);
}
