// Restart: 2000 steps straight equals 1000 steps, save, load, 1000 steps, bit
// for bit (positions, velocities, springs, energy budget).
#include <gtest/gtest.h>

#include <omp.h>

#include <cstdint>
#include <cstring>

#include <filesystem>
#include <unistd.h>

#include "support/scenes.h"
#include "support/state_compare.h"
#include "support/thread_switching.h"
#include "virtual_triaxial/io/sample_file.h"
#include "virtual_triaxial/dem/simulation.h"

using namespace vt::dem;
using vt::test::expect_same_state;
using vt::test::same_bits;

using vt::test::loaded_packing;


TEST(Restart, InMemoryStateContinuesBitForBit) {
  const SimulationState start = loaded_packing();
  ASSERT_GT(start.contacts.size(), 300u) << "the test needs a loaded contact network";
  Simulation straight(start);
  ASSERT_EQ(straight.run(2000), 2000);

  Simulation first(start);
  ASSERT_EQ(first.run(1000), 1000);
  Simulation second(first.state());
  ASSERT_EQ(second.run(1000), 1000);

  expect_same_state(straight.state(), second.state());
  // And the run did move: springs differ from the start.
  EXPECT_FALSE(same_bits(start.particles.frac, straight.state().particles.frac));
}

TEST(Restart, ThroughASampleFileContinuesBitForBit) {
  const SimulationState start = loaded_packing();
  Simulation straight(start);
  ASSERT_EQ(straight.run(2000), 2000);

  Simulation first(start);
  ASSERT_EQ(first.run(1000), 1000);
  const std::string path =
      (std::filesystem::temp_directory_path() / ("vt_restart_" + std::to_string(::getpid()) + ".h5")).string();
  vt::io::write_sample(path, first.state(), vt::io::SampleMetadata{});
  Simulation second(vt::io::read_sample(path));
  std::filesystem::remove(path);
  ASSERT_EQ(second.run(1000), 1000);
  expect_same_state(straight.state(), second.state());
}

TEST(Restart, ResultIsIndependentOfThreadCount) {
  const SimulationState start = loaded_packing();
  omp_set_num_threads(1);
  Simulation one(start);
  one.run(500);
  omp_set_num_threads(2);
  Simulation two(start);
  two.run(500);
  omp_set_num_threads(omp_get_num_procs());
  expect_same_state(one.state(), two.state());
}

// A team of one thread while omp_get_max_threads() says two (parallel
// regions made inactive, as an enclosing parallel region or OpenMP's
// dynamic teams can): the one-thread path, every particle's sums zeroed and
// made in its pair loop, the one-thread bits.
TEST(Restart, ATeamOfOneWhereTwoArePlannedGivesTheOneThreadBits) {
  const SimulationState start = vt::test::spatially_sorted(loaded_packing(1600));
  omp_set_num_threads(1);
  Simulation one(start);
  ASSERT_EQ(one.run(200), 200) << one.failure();
  omp_set_num_threads(2);
  const int levels = omp_get_max_active_levels();
  omp_set_max_active_levels(0);
  Simulation serialized(start);
  ASSERT_EQ(serialized.run(100), 100) << serialized.failure();
  EXPECT_FALSE(serialized.split_used());
  omp_set_max_active_levels(levels);
  ASSERT_EQ(serialized.run(100), 100) << serialized.failure();  // then a real team
  EXPECT_TRUE(serialized.split_used());
  omp_set_num_threads(omp_get_num_procs());
  expect_same_state(one.state(), serialized.state());
}

// One thread sums each particle's forces inside the pair loop; more
// threads evaluate runs of 512-particle chunks in parallel, each summing its
// own particles, with the pairs owned in another run whose partner is home
// evaluated again as ghosts before and after its chunks (split_sums.h).
// Both add the same terms in the same (list) order, so over a sample of
// several chunks, where pairs cross chunk boundaries both ways, the runs
// agree bit for bit. Spatially sorted storage (ids no longer in storage
// order), so that particles also have entries of owners stored after them.
TEST(Restart, PairLoopSumsAcrossChunksDoNotDependOnTheThreads) {
  const SimulationState start = vt::test::spatially_sorted(loaded_packing(1600));
  ASSERT_GT(start.particles.size(), 3u * 512u);
  ASSERT_GT(start.contacts.size(), 1200u) << "the test needs a loaded contact network";
  omp_set_num_threads(1);
  Simulation one(start);
  ASSERT_EQ(one.run(400), 400) << one.failure();
  EXPECT_FALSE(one.split_used());
  EXPECT_TRUE(vt::test::has_owner_stored_after(one.neighbor_list()))
      << "the test needs particles summed across owners stored before and after them";
  omp_set_num_threads(2);
  Simulation two(start);
  ASSERT_EQ(two.run(400), 400) << two.failure();
  // Several threads: every particle summed by its thread's pair loop, the
  // pairs crossing runs evaluated again by the partner's thread as ghosts
  // (split_sums.h), no completions.
  EXPECT_GT(two.ghost_pairs(), 0u);
  EXPECT_LT(two.ghost_pairs(), two.neighbor_list().pairs().size() / 4) << "most pairs are evaluated once";
  omp_set_num_threads(3);
  Simulation three(start);
  ASSERT_EQ(three.run(400), 400) << three.failure();
  EXPECT_GT(three.ghost_pairs(), two.ghost_pairs()) << "three runs have more ends than two";
  omp_set_num_threads(omp_get_num_procs());
  expect_same_state(one.state(), two.state());
  expect_same_state(one.state(), three.state());
  EXPECT_FALSE(same_bits(start.particles.omega, one.state().particles.omega));
}

// The sphere kernel with the contact dashpots (viscous damping) on a team:
// two and three threads give the one-thread bits.
TEST(Restart, SplitSumsWithContactDashpotsGiveTheOneThreadBits) {
  SimulationState start = vt::test::spatially_sorted(loaded_packing(1600));
  start.settings.damping = MassDamping(DampingModel::Viscous, 0.5);
  omp_set_num_threads(1);
  Simulation one(start);
  ASSERT_EQ(one.run(300), 300) << one.failure();
  for (int threads : {2, 3}) {
    omp_set_num_threads(threads);
    Simulation more(start);
    ASSERT_EQ(more.run(300), 300) << more.failure();
    EXPECT_TRUE(more.split_used());
    EXPECT_GT(more.ghost_pairs(), 0u);
    expect_same_state(one.state(), more.state());
  }
  omp_set_num_threads(omp_get_num_procs());
}

// Thread counts switched mid-run (as the run-time governor does): the plan
// is remade or kept as the count changes, and the run is the one-thread run
// bit for bit.
TEST(Restart, SwitchingThreadCountsMidRunKeepsTheBits) {
  vt::test::expect_switching_threads_keeps_the_bits(vt::test::spatially_sorted(loaded_packing(1600)), 50);
}

// The two threads' runs re-cut mid-run (a thread turned slower): the plan
// and the ghosts are made again at each re-cut and carried between them.
TEST(Restart, ReCuttingTheThreadRunsMidRunKeepsTheBits) {
  vt::test::expect_recuts_keep_the_bits(vt::test::spatially_sorted(loaded_packing(2400)), 4);
}
