// Spheroid runs restart and do not depend on the thread count, bit for bit;
// pairs found apart sleep without changing any result (dem/contact_forces.h,
// set_motion_clock): a sheared packing, fast gases, a spinning tip and a
// compressing cell (one case per term of the motion bound).
#include <gtest/gtest.h>

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <vector>
#include <filesystem>
#include <string>
#include <utility>

#include "support/omp_threads.h"
#include "support/scenes.h"
#include "support/spheroid_scenes.h"
#include "support/thread_switching.h"
#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/dem/periodic_tiling.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/dem/split_sums.h"
#include "virtual_triaxial/dem/thread_runs.h"
#include "virtual_triaxial/io/sample_file.h"

using namespace vt::dem;
using vt::test::add_at;
using vt::test::axis_rotation;
using vt::test::dense_spheroid_gas;
using vt::test::expect_same_state;
using vt::test::loaded_spheroid_packing;
using vt::test::PairScene;
using vt::test::same_bits;


TEST(SpheroidRestart, ThroughASampleFileContinuesBitForBit) {
  const SimulationState start = loaded_spheroid_packing();
  {
    Simulation probe(start);
    ASSERT_TRUE(probe.step(true));
    ASSERT_GT(probe.measures().contacts, 300) << "the test needs a loaded contact network";
  }
  Simulation straight(start);
  ASSERT_EQ(straight.run(2000), 2000) << straight.failure();

  Simulation first(start);
  ASSERT_EQ(first.run(1000), 1000);
  const std::string path =
      (std::filesystem::temp_directory_path() / ("vt_spheroid_restart_" + std::to_string(getpid()) + ".h5")).string();
  vt::io::write_sample(path, first.state(), vt::io::SampleMetadata{});
  const SimulationState loaded = vt::io::read_sample(path);
  std::filesystem::remove(path);
  EXPECT_TRUE(same_bits(loaded.particles.orientation, first.state().particles.orientation));
  std::size_t cached = 0;
  for (const ContactHistory& c : loaded.contacts) cached += c.cache.valid ? 1 : 0;
  EXPECT_GT(cached, 300u) << "warm-start normals travel with the sample";
  Simulation second(loaded);
  ASSERT_EQ(second.run(1000), 1000);
  expect_same_state(straight.state(), second.state());
  EXPECT_EQ(straight.spheroid_contact_stats().fallbacks, 0u);
}

TEST(SpheroidRestart, ResultsDoNotDependOnTheThreadCount) {
  // spatially sorted: particles also have entries of owners stored after them
  const SimulationState start = vt::test::spatially_sorted(loaded_spheroid_packing());
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  Simulation one(start);
  ASSERT_EQ(one.run(300), 300);
  EXPECT_FALSE(one.split_used());
  EXPECT_TRUE(vt::test::has_owner_stored_after(one.neighbor_list()))
      << "the test needs particles summed across owners stored before and after them";
  omp_set_num_threads(3);
  Simulation three(start);
  ASSERT_EQ(three.run(300), 300);
  EXPECT_TRUE(three.split_used());
  omp_set_num_threads(before);
  expect_same_state(one.state(), three.state());
}

TEST(SpheroidRestart, PairsCrossingThreadRunsGiveTheOneThreadBits) {
  // 2 x 2 x 2 tiles of the loaded packing, sorted in space: 2400 spheroids
  // in 5 chunks, so two and three threads take runs of whole chunks with
  // pairs crossing them; each thread's pair loop sums its run, the pairs
  // owned in other runs evaluated again as ghosts (SplitSums::ghosts, with
  // the thread's own copies of their solver caches and wake times).
  const SimulationState start =
      vt::test::spatially_sorted(tile_periodic(loaded_spheroid_packing(), 2, 2, 2));
  const std::size_t n = start.particles.size();
  ASSERT_GT(n, 4u * static_cast<std::size_t>(kChunkSize));
  vt::test::RestoreThreads restore;
  omp_set_num_threads(1);
  Simulation one(start);
  ASSERT_EQ(one.run(200), 200) << one.failure();
  // the ghosts of two and three runs (split_sums.h; their order:
  // test_split_sums): exactly the pairs owned in another run than their
  // partner's; the crossings hold contacts, and their particles are few
  const NeighborList& list = one.neighbor_list();
  for (const int threads : {2, 3}) {
    ThreadRuns runs;
    runs.prepare(chunk_count(n), n, threads);
    SplitSums plan;
    plan.prepare(list, n, runs);
    std::vector<int> run_of(n);
    for (int t = 0; t < threads; ++t)
      for (std::int32_t c = runs.run(t).first; c < runs.run(t).second; ++c)
        for (std::size_t p = static_cast<std::size_t>(c) * kChunkSize;
             p < std::min(n, static_cast<std::size_t>(c + 1) * kChunkSize); ++p)
          run_of[p] = t;
    std::size_t crossing_contacts = 0;
    std::vector<std::int32_t> expected, planned, cut;
    for (std::size_t e = 0; e < list.pairs().size(); ++e) {
      const std::int32_t p = list.pairs().partner[e];
      if (run_of[static_cast<std::size_t>(p)] == run_of[static_cast<std::size_t>(list.owners()[e])]) continue;
      expected.push_back(static_cast<std::int32_t>(e));
      cut.push_back(p);
      crossing_contacts += list.pairs().active[e];
    }
    std::sort(cut.begin(), cut.end());
    cut.erase(std::unique(cut.begin(), cut.end()), cut.end());
    for (int t = 0; t < threads; ++t) planned.insert(planned.end(), plan.ghosts(t).begin(), plan.ghosts(t).end());
    std::sort(planned.begin(), planned.end());
    EXPECT_EQ(planned, expected) << threads << " runs";
    EXPECT_EQ(plan.cut_count(), cut.size()) << threads << " runs";
    EXPECT_GT(crossing_contacts, 0u) << threads << " runs";
    EXPECT_GT(cut.size(), 0u) << threads << " runs";
    EXPECT_LT(cut.size(), n / 2) << "most particles are summed by their thread's pair loop alone";
  }
  for (const int threads : {2, 3}) {
    omp_set_num_threads(threads);
    Simulation more(start);
    ASSERT_EQ(more.run(200), 200) << more.failure();
    expect_same_state(one.state(), more.state());
  }
}

// Thread counts switched mid-run (as the run-time governor does), back to a
// count whose plan is kept after one-thread steps: each thread's ghost
// copies (springs, solver caches, wake times) are taken from the list
// again, and the run is the one-thread run bit for bit.
TEST(SpheroidRestart, SwitchingThreadCountsMidRunKeepsTheBits) {
  vt::test::expect_switching_threads_keeps_the_bits(
      vt::test::spatially_sorted(tile_periodic(loaded_spheroid_packing(), 2, 2, 2)), 30);
}

// The two threads' runs re-cut mid-run: each thread's ghost copies
// (springs, solver caches, wake times) carried between the re-cuts and
// taken again at each: the one-thread run bit for bit.
TEST(SpheroidRestart, ReCuttingTheThreadRunsMidRunKeepsTheBits) {
  vt::test::expect_recuts_keep_the_bits(
      vt::test::spatially_sorted(tile_periodic(loaded_spheroid_packing(), 2, 2, 2)), 4);
}

namespace {

/// Runs `steps` steps from `start` with sleeping off and on; the states must
/// agree bit for bit. The solver counters of both runs are returned.
void run_awake_and_asleep(const SimulationState& start, std::int64_t steps, SpheroidContactStats* awake_stats,
                          SpheroidContactStats* asleep_stats) {
  Simulation awake(start);
  awake.set_sleep_apart_pairs(false);
  Simulation sleeping(start);
  ASSERT_EQ(awake.run(steps), steps) << awake.failure();
  ASSERT_EQ(sleeping.run(steps), steps) << sleeping.failure();
  expect_same_state(awake.state(), sleeping.state());
  *awake_stats = awake.spheroid_contact_stats();
  *asleep_stats = sleeping.spheroid_contact_stats();
}

}  // namespace

TEST(SpheroidSleep, PairsFoundApartSleepWithoutChangingAnyResult) {
  // Sheared loaded packing: letting pairs in reach that were found apart
  // sleep (ContactForces::set_motion_clock) must skip many evaluations and
  // change nothing, bit for bit: the motion-clock bound says they cannot
  // have touched, and evaluating an apart pair has no effect.
  SpheroidContactStats awake, sleeping;
  ASSERT_NO_FATAL_FAILURE(run_awake_and_asleep(loaded_spheroid_packing(), 2000, &awake, &sleeping));
  EXPECT_EQ(awake.asleep, 0u);
  const double per_step = static_cast<double>(sleeping.asleep) / (2000.0 * 300.0);
  std::printf("[ sleep ] pairs asleep per particle-step %.2f; solves %llu awake, %llu sleeping\n", per_step,
              static_cast<unsigned long long>(awake.solves), static_cast<unsigned long long>(sleeping.solves));
  EXPECT_GT(per_step, 0.2);  // a real share of the pairs in reach sleeps
  EXPECT_EQ(sleeping.fallbacks, 0u);
}

TEST(SpheroidSleep, FastGasesGiveTheSameResultsAsleepOrAwake) {
  // Dense frictionless gases: 10 m/s and 2000 rad/s (translation drives the
  // motion clock), then spin alone at 2e4 rad/s (the a - b term does): the
  // collisions must be found on the same step as without sleeping.
  for (const bool spin_only : {false, true}) {
    SimulationState start = dense_spheroid_gas(0.1);
    if (spin_only) vt::test::randomize_velocities(start.particles, 0.0, 2e4, 13);
    SpheroidContactStats awake, sleeping;
    ASSERT_NO_FATAL_FAILURE(run_awake_and_asleep(start, 3000, &awake, &sleeping));
    std::printf("[ sleep ] gas%s: pairs asleep per particle-step %.2f\n", spin_only ? " (spin only)" : "",
                static_cast<double>(sleeping.asleep) / (3000.0 * 200.0));
    EXPECT_GT(sleeping.asleep, 0u);
  }
}

namespace {

/// Steps until the pair scene first has a contact, awake and asleep (-1: none
/// within max_steps) under isotropic compression at eps' = eps_rate (0: a
/// fixed cell). Checks that pairs slept.
std::pair<std::int64_t, std::int64_t> first_contact_awake_and_asleep(const PairScene& s, std::int64_t max_steps,
                                                                    double eps_rate) {
  const SimulationSettings st = vt::test::undamped(0.1, 0.0);
  std::int64_t first[2] = {-1, -1};
  for (const bool sleep : {false, true}) {
    Simulation sim(s.p, s.cell, st);
    sim.set_sleep_apart_pairs(sleep);
    sim.set_strain_rates(Vec3{-1, -1, -1} * (eps_rate / sim.time_scale().t0));
    for (std::int64_t k = 0; k < max_steps && first[sleep] < 0; ++k) {
      EXPECT_TRUE(sim.step(true)) << sim.failure();
      if (sim.measures().contacts > 0) first[sleep] = k;
    }
    if (sleep) {
      EXPECT_GT(sim.spheroid_contact_stats().asleep, 0u);
    }
  }
  return {first[0], first[1]};
}

}  // namespace

TEST(SpheroidSleep, ASpinningTipIsCaughtOnTheStepItTouches) {
  // Rotation alone closes the gap: i spins about z (no translation, no
  // straining) and its tip sweeps into j's side. Only the a - b term of the
  // motion clock runs, and the first contact must come on the same step
  // asleep or awake.
  const double a = 1.2e-3, b = 1e-3;
  PairScene s;
  const Vec3 c{0.01, 0.01, 0.01};
  add_at(s, 0, a, b, {}, c, {}, Vec3{0, 0, 300.0});  // axis along x, turning toward y
  add_at(s, 1, a, b, {}, c + Vec3{0, a + b - 2e-5, 0});  // apart by ~0.18 mm while i lies along x
  const auto [awake, asleep] = first_contact_awake_and_asleep(s, 200000, 0.0);
  std::printf("[ sleep ] spinning tip: first contact at step %lld awake, %lld asleep\n",
              static_cast<long long>(awake), static_cast<long long>(asleep));
  ASSERT_GT(awake, 10);  // apart at the start, touching later
  EXPECT_EQ(awake, asleep);
}

TEST(SpheroidSleep, ACompressingCellIsCaughtOnTheStepItBringsAPairIntoTouch) {
  // The cell's deformation alone closes the gap (particles at rest, isotropic
  // compression): only the ||F - I|| term of the motion clock runs.
  const double a = 1.2e-3, b = 1e-3;
  PairScene s;
  const Vec3 c{0.01, 0.01, 0.01};
  add_at(s, 0, a, b, {}, c);
  add_at(s, 1, a, b, axis_rotation({0, 0, 1}, 0.3), c + Vec3{0, 2.03e-3, 0});  // apart by ~11 um
  const auto [awake, asleep] = first_contact_awake_and_asleep(s, 300000, 1e-6);
  std::printf("[ sleep ] compressing cell: first contact at step %lld awake, %lld asleep\n",
              static_cast<long long>(awake), static_cast<long long>(asleep));
  ASSERT_GT(awake, 10);
  EXPECT_EQ(awake, asleep);
}
