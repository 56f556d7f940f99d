// PhaseTimes (dem/phase_times.h): where a step's time goes per thread.
//   - the arithmetic: busy = sum of the phases, waits = both regions less
//     busy, reset zeroes everything, a thread without a slot reads 0;
//   - on a spatially sorted sphere packing stepped by Simulation on one and
//     on two threads: every thread of the team times its own pair loop and
//     its integration (> 0), no thread's phases exceed the regions that hold
//     them (waits >= 0: the regions are timed around the team, the phases
//     inside it, with the same clock), ghosts are timed only on several
//     threads, and reset_phase_times() starts from zero.
#include <gtest/gtest.h>

#include <omp.h>

#include "support/scenes.h"
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
  pt.add(1, PhaseTimes::Ghosts, 0.125);
  pt.add_region(PhaseTimes::Forces, 2.5);
  pt.add_region(PhaseTimes::Integration, 0.5);
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
  EXPECT_EQ(pt.region(PhaseTimes::Forces), 0.0);
  EXPECT_EQ(pt.threads(), 2);
  EXPECT_STREQ(PhaseTimes::name(PhaseTimes::Ghosts), "ghosts");
  EXPECT_STREQ(PhaseTimes::name(PhaseTimes::Integrate), "integrate");
}

namespace {

/// Steps a sorted 1600-sphere packing (4 chunks) on `threads` threads and
/// checks the invariants of its phase times.
void check_steps_on(int threads) {
  omp_set_num_threads(1);
  Simulation sim(vt::test::spatially_sorted(vt::test::loaded_packing(1600)));
  ASSERT_EQ(sim.run(5), 5) << sim.failure();
  omp_set_num_threads(threads);
  ASSERT_EQ(sim.run(5), 5) << sim.failure();  // the team's plan is made
  sim.reset_phase_times();
  const PhaseTimes& pt = sim.phase_times();
  EXPECT_EQ(pt.busy(0), 0.0);
  EXPECT_EQ(pt.region(PhaseTimes::Forces), 0.0);
  ASSERT_EQ(sim.run(20), 20) << sim.failure();
  ASSERT_GE(pt.threads(), threads);
  EXPECT_GT(pt.region(PhaseTimes::Forces), 0.0);
  EXPECT_GT(pt.region(PhaseTimes::Integration), 0.0);
  for (int t = 0; t < threads; ++t) {
    EXPECT_GT(pt.seconds(t, PhaseTimes::Pairs), 0.0) << threads << " threads, thread " << t;
    EXPECT_GT(pt.seconds(t, PhaseTimes::Integrate), 0.0) << threads << " threads, thread " << t;
    EXPECT_GE(pt.waits(t), 0.0) << threads << " threads, thread " << t << ": phases outside their regions";
    EXPECT_LE(pt.seconds(t, PhaseTimes::Integrate), pt.region(PhaseTimes::Integration));
    if (threads == 1) {
      EXPECT_EQ(pt.seconds(t, PhaseTimes::Ghosts), 0.0);
    }
  }
  if (threads > 1) {
    ASSERT_TRUE(sim.split_used());
    ASSERT_GT(sim.split_ghosts(), 0u);
    EXPECT_GT(pt.seconds(0, PhaseTimes::Ghosts) + pt.seconds(1, PhaseTimes::Ghosts), 0.0);
  }
  omp_set_num_threads(omp_get_num_procs());
}

}  // namespace

TEST(PhaseTimes, EveryThreadTimesItsPairLoopAndIntegrationInsideTheRegions) {
  check_steps_on(1);
  check_steps_on(2);
}
