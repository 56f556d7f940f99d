// SplitSums (dem/split_sums.h): the plan by which several threads make the
// per-particle sums of the sphere pair loop. Its invariants, checked on the
// neighbour list of a loaded, spatially sorted packing of several chunks
// (the sums themselves: Restart.PairLoopSumsEqualTheGatherAcrossChunks,
// bit for bit on one, two and three threads):
//   - a particle is sole (takes its thread's buffer sum) exactly when every
//     gather slot of it is owned in its own thread's run; the others gather;
//   - foreign(t) is the set of partners outside run t of the pairs owned in
//     run t (their buffer slots are zeroed by thread t), sorted, once each;
//   - the plan follows the runs.
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <set>
#include <vector>

#include "support/scenes.h"
#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/dem/split_sums.h"
#include "virtual_triaxial/dem/thread_runs.h"

using namespace vt::dem;

namespace {

/// The plan's invariants for `threads` equal runs over the list of `sim`;
/// returns how many particles are not sole.
std::size_t check_plan(const Simulation& sim, int threads) {
  const NeighborList& list = sim.neighbor_list();
  const std::size_t n = sim.particles().size();
  ThreadRuns runs;
  runs.prepare(chunk_count(n), n, threads);
  SplitSums plan;
  plan.prepare(list, n, runs);

  std::vector<int> run_of(n);
  for (int t = 0; t < threads; ++t) {
    const auto [c0, c1] = runs.run(t);
    for (std::size_t p = static_cast<std::size_t>(c0) * kChunkSize;
         p < std::min(n, static_cast<std::size_t>(c1) * kChunkSize); ++p)
      run_of[p] = t;
  }
  const std::vector<std::int32_t>& goff = list.gather_offsets();
  const std::vector<std::int32_t>& gcode = list.gather_codes();
  const std::vector<std::int32_t>& owners = list.owners();
  const auto slot_run = [&](std::int32_t g) { return run_of[static_cast<std::size_t>(owners[gcode[g] >> 2])]; };

  std::size_t not_sole = 0;
  for (std::int32_t p = 0; p < static_cast<std::int32_t>(n); ++p) {
    bool own = true;
    for (std::int32_t g = goff[p]; g < goff[p + 1]; ++g) own = own && slot_run(g) == run_of[p];
    EXPECT_EQ(plan.sole(p), own) << "particle " << p;
    not_sole += own ? 0 : 1;
  }
  EXPECT_EQ(plan.gathered(), not_sole);

  const std::vector<std::int32_t>& partner = list.pairs().partner;
  for (int t = 0; t < threads; ++t) {
    std::set<std::int32_t> expected;
    for (std::size_t e = 0; e < partner.size(); ++e)
      if (run_of[static_cast<std::size_t>(owners[e])] == t && run_of[static_cast<std::size_t>(partner[e])] != t)
        expected.insert(partner[e]);
    const std::vector<std::int32_t>& f = plan.foreign(t);
    EXPECT_EQ(std::set<std::int32_t>(f.begin(), f.end()), expected) << "thread " << t;
    EXPECT_TRUE(std::is_sorted(f.begin(), f.end()));
    EXPECT_EQ(f.size(), expected.size()) << "no duplicates";
  }
  return not_sole;
}

}  // namespace

TEST(SplitSums, PlanMarksTheParticlesAtTheRunsEnds) {
  omp_set_num_threads(1);
  Simulation sim(vt::test::spatially_sorted(vt::test::loaded_packing(1600)));
  ASSERT_EQ(sim.run(20), 20) << sim.failure();
  omp_set_num_threads(omp_get_num_procs());
  const std::size_t n = sim.particles().size();
  ASSERT_GT(n, 3u * static_cast<std::size_t>(kChunkSize));
  ASSERT_TRUE(vt::test::has_owner_stored_after(sim.neighbor_list()));
  const std::size_t two = check_plan(sim, 2), three = check_plan(sim, 3);
  EXPECT_GT(two, 0u);
  EXPECT_LT(two, n / 2) << "most particles are sole";
  EXPECT_GT(three, two) << "three runs have more ends than two";
}

TEST(SplitSums, PlanIsRemadeWhenTheRunsChange) {
  omp_set_num_threads(1);
  Simulation sim(vt::test::loaded_packing(1600));
  ASSERT_EQ(sim.run(5), 5) << sim.failure();
  omp_set_num_threads(omp_get_num_procs());
  const std::size_t n = sim.particles().size();
  ThreadRuns runs;
  runs.prepare(chunk_count(n), n, 2);
  SplitSums plan;
  plan.prepare(sim.neighbor_list(), n, runs);
  const std::size_t two = plan.gathered();
  runs.prepare(chunk_count(n), n, 3);
  plan.prepare(sim.neighbor_list(), n, runs);
  EXPECT_GT(plan.gathered(), two) << "three runs: the plan was remade";
  runs.prepare(chunk_count(n), n, 2);
  plan.prepare(sim.neighbor_list(), n, runs);
  EXPECT_EQ(plan.gathered(), two);
}
