// SplitSums (dem/split_sums.h): the plan by which several threads make the
// per-particle sums of the pair loop without a gather of every particle. Its
// invariants, checked on the neighbour list of a loaded, spatially sorted
// packing of several chunks (the sums themselves:
// Restart.PairLoopSumsEqualTheGatherAcrossChunks, bit for bit on one, two
// and three threads):
//   - ghosts_before(t) / ghosts_after(t) are exactly the entries owned in a
//     lower / higher run whose partner is in run t, ascending, so thread t
//     adds every term of a home particle in list order;
//   - boundary(t) is exactly the entries owned in run t with a partner in
//     a higher run, and every ghost of ghosts_before is some run's boundary
//     entry, with its own slot in the ghost spring buffers (those of
//     ghosts_after have none: their terms come from the pair states);
//     contacts occur among the ghosts on both sides;
//   - the ghost springs are the list's springs when the plan is made, and
//     after a step the ones the owners put for the next one;
//   - the completions after the pair loops: every partner of a pair owned
//     in another run exactly once, as an edge particle (spheroid lists,
//     some pair owned in a lower run) or a tail starting at its first slot
//     owned in a higher run, shared among the threads in particle order and in about
//     equal slots (the sums themselves: Restart.
//     PairLoopSumsEqualTheGatherAcrossChunks,
//     SpheroidRestart.PairsCrossingThreadRunsGiveTheOneThreadBits);
//   - the plan follows the runs and the steps.
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

bool same(const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

std::vector<std::int32_t> entries(const std::vector<SplitSums::Ghost>& g) {
  std::vector<std::int32_t> e;
  for (const SplitSums::Ghost& x : g) e.push_back(x.entry);
  return e;
}

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
  p.plan.prepare(list, n, runs, 1);
  p.run_of = run_of_particles(runs, n);
  return p;
}

/// The plan's invariants for `threads` equal runs; returns the ghost count.
std::size_t check_plan(const Simulation& sim, int threads) {
  const NeighborList& list = sim.neighbor_list();
  const std::size_t n = sim.particles().size();
  const auto [plan, run_of] = plan_of(list, n, threads);
  const std::vector<std::int32_t>& owners = list.owners();
  const std::vector<std::int32_t>& partner = list.pairs().partner;
  const std::vector<Vec3>& spring = list.pairs().spring;
  std::size_t ghosts = 0;
  std::size_t touching_before = 0, touching_after = 0;
  std::vector<bool> slot_seen(plan.ghost_count(), false);
  for (int t = 0; t < threads; ++t) {
    std::vector<std::int32_t> before, after, boundary;
    for (std::size_t e = 0; e < partner.size(); ++e) {
      const int to = run_of[static_cast<std::size_t>(owners[e])];
      const int tp = run_of[static_cast<std::size_t>(partner[e])];
      if (tp == t && to < t) before.push_back(static_cast<std::int32_t>(e));
      if (tp == t && to > t) after.push_back(static_cast<std::int32_t>(e));
      if (to == t && tp > t) boundary.push_back(static_cast<std::int32_t>(e));
    }
    EXPECT_EQ(entries(plan.ghosts_before(t)), before) << "thread " << t;
    EXPECT_EQ(entries(plan.ghosts_after(t)), after) << "thread " << t;
    EXPECT_EQ(plan.boundary(t), boundary) << "thread " << t;
    ghosts += before.size();
    for (const SplitSums::Ghost& x : plan.ghosts_after(t)) EXPECT_EQ(x.slot, -1) << "no spring: a tail";
    for (const auto* g : {&plan.ghosts_before(t)})
      for (const SplitSums::Ghost& x : *g) {
        // its slot: its place among its owner's boundary entries, used once
        const int to = run_of[static_cast<std::size_t>(owners[static_cast<std::size_t>(x.entry)])];
        const std::vector<std::int32_t>& b = plan.boundary(to);
        const auto at = std::find(b.begin(), b.end(), x.entry);
        EXPECT_NE(at, b.end());
        if (at == b.end()) continue;
        EXPECT_EQ(x.slot, plan.boundary_slot(to) + static_cast<std::int32_t>(at - b.begin()));
        EXPECT_LT(static_cast<std::size_t>(x.slot), slot_seen.size());
        if (static_cast<std::size_t>(x.slot) >= slot_seen.size()) continue;
        EXPECT_FALSE(slot_seen[static_cast<std::size_t>(x.slot)]);
        slot_seen[static_cast<std::size_t>(x.slot)] = true;
        // a ghost reads the spring its owner's loop starts from
        EXPECT_TRUE(same(plan.ghost_springs()[x.slot], spring[static_cast<std::size_t>(x.entry)]));
      }
    for (const SplitSums::Ghost& x : plan.ghosts_before(t)) touching_before += list.pairs().active[x.entry] ? 1 : 0;
    for (const SplitSums::Ghost& x : plan.ghosts_after(t)) touching_after += list.pairs().active[x.entry] ? 1 : 0;
  }
  EXPECT_EQ(plan.ghost_count(), ghosts);
  // contacts among the ghosts owned both before and after a run (so the
  // sums test covers both sides)
  EXPECT_GT(touching_before, 0u);
  EXPECT_GT(touching_after, 0u);
  return ghosts;
}

}  // namespace

TEST(SplitSums, GhostsAreThePairsThatCrossRunsInListOrder) {
  const Simulation sim = sorted_packing();
  const std::size_t n = sim.particles().size();
  ASSERT_GT(n, 3u * static_cast<std::size_t>(kChunkSize));
  ASSERT_TRUE(vt::test::has_owner_stored_after(sim.neighbor_list()));
  ASSERT_GT(sim.state().contacts.size(), 1000u) << "the test needs loaded springs";
  const std::size_t two = check_plan(sim, 2), three = check_plan(sim, 3);
  EXPECT_GT(two, 0u);
  EXPECT_LT(two, sim.neighbor_list().pairs().size() / 4) << "most pairs are evaluated once";
  EXPECT_GT(three, two) << "three runs have more ends than two";
}

TEST(SplitSums, GhostSpringsFollowTheStepsAndThePlan) {
  const Simulation sim = sorted_packing();
  const NeighborList& list = sim.neighbor_list();
  const std::size_t n = sim.particles().size();
  ThreadRuns runs;
  runs.prepare(chunk_count(n), n, 2);
  SplitSums plan;
  EXPECT_FALSE(plan.current(list, n, runs, 1));
  plan.prepare(list, n, runs, 1);
  EXPECT_TRUE(plan.current(list, n, runs, 1)) << "prepared for step 1";
  EXPECT_FALSE(plan.current(list, n, runs, 2)) << "step 1 not finished yet";
  // the owners put this step's springs; the next step's ghosts read them
  ASSERT_FALSE(plan.boundary(0).empty());
  const std::int32_t e = plan.boundary(0).front(), slot = plan.boundary_slot(0);
  const Vec3 put{1.0, -2.0, 3.0};
  plan.next_ghost_springs()[slot] = put;
  plan.finish_step(1);
  EXPECT_TRUE(plan.current(list, n, runs, 2));
  EXPECT_TRUE(same(plan.ghost_springs()[slot], put));
  // a step taken without the plan (say, on one thread): refilled from the list
  EXPECT_FALSE(plan.current(list, n, runs, 3));
  plan.prepare(list, n, runs, 3);
  EXPECT_TRUE(same(plan.ghost_springs()[slot], list.pairs().spring[static_cast<std::size_t>(e)]));
  plan.finish_step(3);
  EXPECT_TRUE(plan.current(list, n, runs, 4));
  // new runs: a new plan
  runs.prepare(chunk_count(n), n, 3);
  EXPECT_FALSE(plan.current(list, n, runs, 4));
}

namespace {

/// The completions of `list` (sphere or spheroid) on `threads` equal runs:
/// every partner of a pair owned in another run exactly once (spheroids: an
/// edge particle when some such pair is owned in a lower run; otherwise a
/// tail, whose slot starts the slots owned in higher runs), each thread's
/// share ascending, the shares consecutive in particle order (edge particles
/// and tails together) and about equal in slots read.
/// Returns {edge particles, tails}.
std::pair<std::size_t, std::size_t> check_completions(const NeighborList& list, std::size_t n, int threads) {
  const auto [plan, run_of] = plan_of(list, n, threads);
  const std::vector<std::int32_t>& owners = list.owners();
  const std::vector<std::int32_t>& partner = list.pairs().partner;
  const std::vector<std::int32_t>& goff = list.gather_offsets();
  const std::vector<std::int32_t>& gcode = list.gather_codes();
  std::vector<bool> lower(n, false), higher(n, false);
  for (std::size_t e = 0; e < partner.size(); ++e) {
    const auto j = static_cast<std::size_t>(partner[e]);
    const int to = run_of[static_cast<std::size_t>(owners[e])];
    if (to < run_of[j]) lower[j] = true;
    if (to > run_of[j]) higher[j] = true;
  }
  std::vector<std::int32_t> edge, tail;  // ascending = run by run
  for (std::size_t j = 0; j < n; ++j) {
    if (lower[j] && list.has_spheroids()) {
      edge.push_back(static_cast<std::int32_t>(j));
    } else if (higher[j]) {
      tail.push_back(static_cast<std::int32_t>(j));
    }
  }
  std::vector<std::int32_t> edge_shares, tail_shares;
  std::vector<std::int64_t> slots(static_cast<std::size_t>(threads), 0);
  std::int64_t largest = 0;
  std::int32_t last = -1;  // the last particle of the shares before
  for (int t = 0; t < threads; ++t) {
    std::int64_t& mine = slots[static_cast<std::size_t>(t)];
    std::int32_t first = INT32_MAX, most = -1;
    std::vector<std::int32_t> mine_all = plan.edge_particles(t);
    for (const SplitSums::Tail& x : plan.edge_tails(t)) mine_all.push_back(x.particle);
    for (const std::int32_t j : mine_all) {
      first = std::min(first, j);
      most = std::max(most, j);
    }
    if (most >= 0) {
      EXPECT_GT(first, last) << "shares in particle order: thread " << t;
      last = most;
    }
    for (const std::int32_t j : plan.edge_particles(t)) {
      edge_shares.push_back(j);
      mine += goff[static_cast<std::size_t>(j) + 1] - goff[static_cast<std::size_t>(j)];
      largest = std::max<std::int64_t>(largest, goff[static_cast<std::size_t>(j) + 1] - goff[static_cast<std::size_t>(j)]);
    }
    for (const SplitSums::Tail& x : plan.edge_tails(t)) {
      tail_shares.push_back(x.particle);
      const auto i = static_cast<std::size_t>(x.particle);
      mine += goff[i + 1] - x.slot;
      largest = std::max<std::int64_t>(largest, goff[i + 1] - x.slot);
      // slots before x.slot: owned in the particle's run or lower; from it: higher runs
      for (std::int32_t g = goff[i]; g < goff[i + 1]; ++g) {
        const std::int32_t code = gcode[static_cast<std::size_t>(g)];
        const bool from_higher = (code & 2) == 0 && run_of[static_cast<std::size_t>(owners[static_cast<std::size_t>(code >> 2)])] > run_of[i];
        EXPECT_EQ(from_higher, g >= x.slot) << "particle " << x.particle << ", slot " << g;
      }
    }
  }
  EXPECT_EQ(edge_shares, edge) << threads << " threads";
  EXPECT_EQ(tail_shares, tail) << threads << " threads";
  std::int64_t total = 0;
  for (const std::int64_t s : slots) total += s;
  for (int t = 0; t < threads; ++t)
    EXPECT_LE(slots[static_cast<std::size_t>(t)], total / threads + largest + 1) << "share of thread " << t;
  return {edge.size(), tail.size()};
}

}  // namespace

TEST(SplitSums, CompletionsTakeEveryCrossingPartnerOnceInSharesOfEqualSlots) {
  // spheres: no edge particles (ghosts), tails
  const Simulation spheres = sorted_packing();
  for (const int threads : {2, 3}) {
    const auto [edge, tails] = check_completions(spheres.neighbor_list(), spheres.particles().size(), threads);
    EXPECT_EQ(edge, 0u);
    EXPECT_GT(tails, 0u);
  }
  // spheroids: 2 x 2 x 2 tiles of 300 loaded spheroids, sorted: 2400 in 5 chunks
  const Simulation sim = stepped_on_one_thread(
      vt::test::spatially_sorted(tile_periodic(vt::test::loaded_spheroid_packing(), 2, 2, 2)), 5);
  ASSERT_TRUE(sim.neighbor_list().has_spheroids());
  for (const int threads : {2, 3}) {
    const auto [edge, tails] = check_completions(sim.neighbor_list(), sim.particles().size(), threads);
    EXPECT_GT(edge, 0u);
    EXPECT_GT(tails, 0u);
  }
}
