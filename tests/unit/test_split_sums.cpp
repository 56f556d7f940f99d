// SplitSums (dem/split_sums.h): the plan by which several threads make the
// per-particle sums of the pair loop without a gather of every particle. Its
// invariants, checked on the neighbour list of a loaded, spatially sorted
// packing of several chunks:
//   - every pair owned in another run than its partner's exactly once as
//     a ghost of the partner's thread, those owned in lower runs first,
//     each part in list order, with contacts among both parts, spheres and
//     spheroids (the sums themselves:
//     Restart.PairLoopSumsAcrossChunksDoNotDependOnTheThreads,
//     SpheroidRestart.PairsCrossingThreadRunsGiveTheOneThreadBits);
//   - the chunks another thread's pair loop reads (shared_chunks, for the
//     integrator's stores: handoff_stores.h) are those holding the owner
//     or the partner of a crossing pair;
//   - the plan follows the runs, N and the list's rebuilds.
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "support/scenes.h"
#include "support/spheroid_scenes.h"
#include "virtual_triaxial/dem/periodic_tiling.h"
#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/dem/split_sums.h"
#include "virtual_triaxial/dem/thread_runs.h"

using namespace vt::dem;

namespace {

/// `start` stepped `steps` steps on one thread (the thread count restored
/// to every CPU after, whatever happens).
Simulation stepped_on_one_thread(const SimulationState& start, std::int64_t steps) {
  omp_set_num_threads(1);
  Simulation sim(start);
  EXPECT_EQ(sim.run(steps), steps) << sim.failure();
  omp_set_num_threads(omp_get_num_procs());
  return sim;
}

Simulation sorted_packing() {
  return stepped_on_one_thread(vt::test::spatially_sorted(vt::test::loaded_packing(1600)), 20);
}

std::vector<int> run_of_particles(const ThreadRuns& runs, std::size_t n) {
  std::vector<int> run_of(n);
  for (int t = 0; t < runs.threads(); ++t) {
    const auto [c0, c1] = runs.run(t);
    for (std::size_t p = static_cast<std::size_t>(c0) * kChunkSize;
         p < std::min(n, static_cast<std::size_t>(c1) * kChunkSize); ++p)
      run_of[p] = t;
  }
  return run_of;
}

/// A plan of `list` over n particles on `threads` equal runs, and the run of every particle.
struct Planned {
  SplitSums plan;
  std::vector<int> run_of;
};
Planned plan_of(const NeighborList& list, std::size_t n, int threads) {
  ThreadRuns runs;
  runs.prepare(chunk_count(n), n, threads);
  Planned p;
  p.plan.prepare(list, n, runs);
  p.run_of = run_of_particles(runs, n);
  return p;
}

}  // namespace

TEST(SplitSums, ThePlanFollowsTheRunsAndTheList) {
  Simulation sim = sorted_packing();
  const NeighborList& list = sim.neighbor_list();
  const std::size_t n = sim.particles().size();
  ThreadRuns runs;
  runs.prepare(chunk_count(n), n, 2);
  SplitSums plan;
  EXPECT_FALSE(plan.current(list, n, runs));
  plan.prepare(list, n, runs);
  EXPECT_TRUE(plan.current(list, n, runs));
  EXPECT_FALSE(plan.current(list, n + 1, runs)) << "another N: another plan";
  const std::size_t ghosts_two = plan.ghost_count();
  // new runs: a new plan, with more ends
  runs.prepare(chunk_count(n), n, 3);
  EXPECT_FALSE(plan.current(list, n, runs));
  plan.prepare(list, n, runs);
  EXPECT_TRUE(plan.current(list, n, runs));
  EXPECT_GT(plan.ghost_count(), ghosts_two) << "three runs have more ends than two";
  // the list rebuilt (the packing shears on): a new plan
  const std::int64_t builds = list.rebuild_count();
  omp_set_num_threads(1);
  for (int k = 0; k < 100 && list.rebuild_count() == builds; ++k) ASSERT_EQ(sim.run(50), 50) << sim.failure();
  omp_set_num_threads(omp_get_num_procs());
  ASSERT_GT(list.rebuild_count(), builds) << "the test needs a rebuild";
  EXPECT_FALSE(plan.current(list, n, runs));
  plan.prepare(list, n, runs);
  EXPECT_TRUE(plan.current(list, n, runs));
}

namespace {

/// The ghosts of `list` (sphere or spheroid) on `threads` equal runs: every entry whose
/// owner and partner are in different runs exactly once, as a ghost of
/// the partner's thread; each thread's ghosts those owned in lower runs
/// (ghosts_lower of them), then those owned in higher runs, each part
/// ascending; contacts among both parts; the particles at the cut counted.
/// Returns the ghosts.
std::size_t check_ghosts(const NeighborList& list, std::size_t n, int threads) {
  const auto [plan, run_of] = plan_of(list, n, threads);
  const std::vector<std::int32_t>& owners = list.owners();
  const std::vector<std::int32_t>& partner = list.pairs().partner;
  std::vector<int> seen(partner.size(), 0);
  std::size_t touching_lower = 0, touching_higher = 0, total = 0;
  for (int t = 0; t < threads; ++t) {
    const std::vector<std::int32_t>& g = plan.ghosts(t);
    const std::size_t lower = plan.ghosts_lower(t);
    if (lower > g.size()) {
      ADD_FAILURE() << "thread " << t << ": more lower-run ghosts than ghosts";
      return 0;
    }
    for (std::size_t k = 0; k < g.size(); ++k) {
      const auto e = static_cast<std::size_t>(g[k]);
      ++seen[e];
      EXPECT_EQ(run_of[static_cast<std::size_t>(partner[e])], t) << "a ghost's partner is home";
      const int to = run_of[static_cast<std::size_t>(owners[e])];
      EXPECT_EQ(k < lower, to < t) << "entry " << e << ": lower runs' ghosts first, then higher runs'";
      EXPECT_NE(to, t);
      if (k > 0 && k != lower) {
        EXPECT_LT(g[k - 1], g[k]) << "each part in list order";
      }
      (to < t ? touching_lower : touching_higher) += list.pairs().active[e] ? 1 : 0;
    }
    total += g.size();
  }
  std::vector<bool> at_cut(n, false);
  std::vector<std::uint8_t> shared(static_cast<std::size_t>(chunk_count(n)), 0);
  for (std::size_t e = 0; e < partner.size(); ++e) {
    const bool crossing = run_of[static_cast<std::size_t>(owners[e])] != run_of[static_cast<std::size_t>(partner[e])];
    EXPECT_EQ(seen[e], crossing ? 1 : 0) << "entry " << e;
    if (crossing) {
      at_cut[static_cast<std::size_t>(partner[e])] = true;
      shared[static_cast<std::size_t>(owners[e] / kChunkSize)] = 1;
      shared[static_cast<std::size_t>(partner[e] / kChunkSize)] = 1;
    }
  }
  EXPECT_EQ(plan.shared_chunks(), shared)
      << "the chunks another thread reads: those of the owners and partners of crossing pairs";
  EXPECT_EQ(plan.cut_count(), static_cast<std::size_t>(std::count(at_cut.begin(), at_cut.end(), true)))
      << "the particles at the cut: partners of a pair owned in another run";
  EXPECT_GT(touching_lower, 0u);
  EXPECT_GT(touching_higher, 0u);
  EXPECT_EQ(plan.ghost_count(), total);
  return total;
}

}  // namespace

TEST(SplitSums, EveryCrossingPairIsOnceAGhostOfItsPartnersThread) {
  // spheres: 1600 loaded, sorted, in 4 chunks
  const Simulation spheres = sorted_packing();
  ASSERT_TRUE(vt::test::has_owner_stored_after(spheres.neighbor_list()));
  ASSERT_GT(spheres.state().contacts.size(), 1000u) << "the test needs loaded contacts";
  for (const int threads : {2, 3}) {
    const std::size_t ghosts = check_ghosts(spheres.neighbor_list(), spheres.particles().size(), threads);
    EXPECT_GT(ghosts, 0u);
    EXPECT_LT(ghosts, spheres.neighbor_list().pairs().size() / 4) << "most pairs are evaluated once";
  }
  // spheroids: 2 x 2 x 2 tiles of 300 loaded spheroids, sorted: 2400 in 5 chunks
  const Simulation sim = stepped_on_one_thread(
      vt::test::spatially_sorted(tile_periodic(vt::test::loaded_spheroid_packing(), 2, 2, 2)), 5);
  ASSERT_TRUE(sim.neighbor_list().has_spheroids());
  for (const int threads : {2, 3}) EXPECT_GT(check_ghosts(sim.neighbor_list(), sim.particles().size(), threads), 0u);
}
