// Runtime thread count (dem/thread_governor.h): the governor keeps the count
// whose measured cost per step is lower (the run's first block, which pays
// for the start, not timed), notices a load that goes within
// exploit_blocks r b + 2 blocks (r: cost ratio, b: the probes' backoff, 1-4),
// spends at most 1/(exploit_blocks + 1) of the time on the worse count and
// less as its probes keep confirming the count, is not flipped by
// one slow block nor timed on steps whose cost is not the count's, and a run
// whose thread count it switches back and forth is bit-identical to a
// one-thread run. Where a room check says the other cores are busy, two
// threads run the first block only and no probe of them runs.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstring>
#include <vector>

#include "support/scenes.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/dem/thread_governor.h"

using namespace vt::dem;

namespace {

/// Run `steps` steps where a step costs cost(threads) seconds.
template <class Cost>
void feed(ThreadGovernor& g, int steps, Cost cost) {
  for (int k = 0; k < steps; ++k) g.record_step(cost(g.threads()));
}

/// Run steps costing cost(threads) until `n` gaps are recorded (at most
/// `max_steps` steps); a gap is the steps run on `running` threads from the
/// start of one probe of the other count to the start of the next (the first
/// gap from now when from_now, else from the first probe). Stops right after
/// the step that starts the probe closing the n-th gap.
template <class Cost>
std::vector<std::int64_t> probe_gaps(ThreadGovernor& g, Cost cost, int running, std::size_t n, int max_steps,
                                     bool from_now) {
  const auto on_running = [&] { return running == 1 ? g.steps_one() : g.steps_max(); };
  std::vector<std::int64_t> gaps;
  std::int64_t at_probe = from_now ? on_running() : -1;
  for (int k = 0; k < max_steps && gaps.size() < n; ++k) {
    const int before = g.threads();
    g.record_step(cost(before));
    if (before == running && g.threads() != running) {
      if (at_probe >= 0) gaps.push_back(on_running() - at_probe);
      at_probe = on_running();
    }
  }
  return gaps;
}

}  // namespace

TEST(ThreadGovernor, KeepsTheCheaperCountAndProbesTheOtherRarely) {
  ThreadGovernor g(2, 10, 0.0, 15);  // blocks of 10 steps
  EXPECT_EQ(g.threads(), 2);
  // busy machine: two threads 3x slower than one
  feed(g, 3100, [](int t) { return t == 1 ? 1e-3 : 3e-3; });
  EXPECT_NEAR(g.cost_one(), 1e-3, 1e-15);
  EXPECT_NEAR(g.cost_max(), 3e-3, 1e-15);
  // after the untimed first block and the two start blocks, one probe block
  // of 10 steps after every 15 x 3 = 45 blocks: the probes take 3/(45 + 3)
  // = 1/16 of the time, less with the backoff
  EXPECT_LE(g.steps_max(), 10 + 10 + 3100 / 46 + 10);
  EXPECT_GE(g.steps_one(), 3100 - (10 + 10 + 3100 / 46 + 10));
  ASSERT_EQ(g.threads(), 1);  // between probes
  // the load goes away: two threads twice as fast; found at the next probe,
  // at most 15 x 3 x kMaxProbeBackoff = 180 blocks later
  const std::int64_t one_before = g.steps_one();
  while (g.threads() == 1 && g.steps_one() - one_before <= 1900) g.record_step(1e-3);
  EXPECT_LE(g.steps_one() - one_before, 1810);
  feed(g, 11, [](int t) { return t == 1 ? 1e-3 : 0.5e-3; });  // the probe block
  EXPECT_EQ(g.threads(), 2);
  const std::int64_t max_before = g.steps_max();  // now 1 thread is probed after 30 blocks
  feed(g, 1600, [](int t) { return t == 1 ? 1e-3 : 0.5e-3; });
  EXPECT_GE(g.steps_max() - max_before, 1600 - 1600 / 31 - 10);
}

TEST(ThreadGovernor, ProbesThatConfirmTheCountComeLessOften) {
  ThreadGovernor g(2, 10, 0.0, 15);  // blocks of 10 steps
  // two threads 3x dearer (r = 3): one-thread blocks between probes 45 b,
  // b doubling with each probe that confirms one thread, up to 4. Each gap
  // holds the first step after the switch back (untimed): 10 x 45 b + 1 steps.
  const auto loaded = [](int t) { return t == 1 ? 1e-3 : 3e-3; };
  const std::vector<std::int64_t> gaps = probe_gaps(g, loaded, 1, 4, 12000, true);
  ASSERT_EQ(gaps.size(), 4u);
  // two threads lost the start: the recheck after ceil(15 x 3 / 8) = 6
  // blocks, the start's one-thread block (its first step untimed) the first
  EXPECT_EQ(gaps[0], 11 + 5 * 10);
  // the recheck confirmed one thread and left b at 1; from then on b = 2, 4
  EXPECT_EQ(gaps[1], 10 * 45 + 1);
  EXPECT_EQ(gaps[2], 10 * 90 + 1);
  EXPECT_EQ(gaps[3], 10 * 180 + 1);
  // the load goes away: two threads twice as fast (r = 2); the next probe
  // wins and the backoff starts again: one thread is probed after 15 x 2 = 30
  // two-thread blocks, and again after 60 once that probe confirmed two threads
  const auto quiet = [](int t) { return t == 1 ? 1e-3 : 0.5e-3; };
  ASSERT_EQ(g.threads(), 2);  // the fourth probe starts
  feed(g, 11, quiet);          // its block, first step untimed: two threads win
  ASSERT_EQ(g.threads(), 2);
  const std::vector<std::int64_t> twos = probe_gaps(g, quiet, 2, 2, 1200, true);
  ASSERT_EQ(twos.size(), 2u);
  // the winning probe block is the first of the 30 (its steps precede the
  // count); the second gap holds the first step after the switch back
  EXPECT_EQ(twos[0], 10 * 29);
  EXPECT_EQ(twos[1], 10 * 60 + 1);
}

TEST(ThreadGovernor, AChangeOfLoadStartsTheProbeSpacingAgain) {
  // costs in powers of two, so every block cost and ratio is exact
  const double unit = 1.0 / 1024;
  ThreadGovernor g(2, 10, 0.0, 15);
  // two threads 4x dearer (r = 4): probes of two threads after 8 (the
  // recheck of the lost start, which leaves b at 1), 60, 120 and 240
  // one-thread blocks; after three probes b = 4
  const auto loaded = [&](int t) { return t == 1 ? unit : 4 * unit; };
  ASSERT_EQ(probe_gaps(g, loaded, 1, 2, 40000, false).size(), 2u);  // three probes
  while (g.threads() == 2) g.record_step(loaded(2));  // the third probe block
  feed(g, 11 + 59 * 10, loaded);  // 60 blocks on one thread (the first step after the switch untimed)
  ASSERT_EQ(g.threads(), 1);
  // one thread gets 8x dearer (two threads now 2x cheaper, r = 2); the
  // second such block switches to two threads and sets b to 1. The dropped
  // count is probed after the first two-thread block (62 blocks since the
  // last probe >= 15 x 2; with b = 4 it would wait for 120), the
  // probe confirms two threads, b = 2: the next probe after 15 x 2 x 2 = 60
  // blocks, the one after it after 120.
  const auto changed = [&](int t) { return t == 1 ? 8 * unit : 4 * unit; };
  feed(g, 20, changed);
  ASSERT_EQ(g.threads(), 2);
  const std::vector<std::int64_t> twos = probe_gaps(g, changed, 2, 2, 4000, false);
  ASSERT_EQ(twos.size(), 2u);
  // each gap starts with the untimed first step after the probe; without the
  // reset b would stay 4: 120 and 120 blocks
  EXPECT_EQ(twos[0], 10 * 60 + 1);
  EXPECT_EQ(twos[1], 10 * 120 + 1);
}

TEST(ThreadGovernor, WithoutRoomTwoThreadsRunTheFirstBlockOnly) {
  ThreadGovernor g(2, 10, 0.0, 15);  // blocks of 10 steps
  bool room = false;
  int asked = 0;
  g.set_room_check([&](int threads) {
    EXPECT_EQ(threads, 2);
    ++asked;
    return room;
  });
  // two threads would be 3x dearer; with no room they run the untimed first
  // block only, and are asked for at its end
  const auto loaded = [](int t) { return t == 1 ? 1e-3 : 3e-3; };
  feed(g, 10, loaded);
  EXPECT_EQ(asked, 1);
  EXPECT_EQ(g.threads(), 1);
  // 2990 steps on one thread: 298 timed blocks (the first step after the
  // change untimed); the room is asked at the end of blocks 1, 3, 7, 15
  // (waits of 1, 2, 4, 8 blocks) and then every 15 blocks: 30, 45, .. 285
  feed(g, 2990, loaded);
  EXPECT_EQ(g.steps_one(), 2990);
  EXPECT_EQ(g.steps_max(), 10);
  EXPECT_EQ(g.cost_max(), 0.0);
  EXPECT_EQ(asked, 1 + 4 + (298 - 15) / 15);
  // room, and two threads twice as fast as one: two threads run within 15
  // blocks, their first block gives their cost (its first step untimed),
  // and they win
  room = true;
  const auto quiet = [](int t) { return t == 1 ? 1e-3 : 0.5e-3; };
  const std::int64_t one_before = g.steps_one();
  while (g.threads() == 1 && g.steps_one() - one_before <= 200) g.record_step(quiet(1));
  EXPECT_LE(g.steps_one() - one_before, 150);
  ASSERT_EQ(g.threads(), 2);
  feed(g, 11, quiet);
  EXPECT_NEAR(g.cost_max(), 0.5e-3, 1e-15);
  EXPECT_EQ(g.threads(), 2);
  feed(g, 200, quiet);
  EXPECT_EQ(g.steps_max(), 10 + 211);
}

TEST(ThreadGovernor, AMomentaryNoRoomCostsOneBlock) {
  // a quiet machine where the first block's snapshot saw a passing task:
  // two threads twice as fast as one, the first answer no, every later one yes
  ThreadGovernor g(2, 10, 0.0, 15);
  int asked = 0;
  g.set_room_check([&](int) { return ++asked > 1; });
  const auto quiet = [](int t) { return t == 1 ? 1e-3 : 0.5e-3; };
  feed(g, 10, quiet);  // the untimed first block: no room
  ASSERT_EQ(g.threads(), 1);
  // one timed block on one thread (its first step untimed), then asked again
  feed(g, 11, quiet);
  EXPECT_EQ(asked, 2);
  EXPECT_EQ(g.threads(), 2);
  EXPECT_NEAR(g.cost_one(), 1e-3, 1e-15);
  // two threads' first timed block: they win and stay
  feed(g, 11, quiet);
  EXPECT_NEAR(g.cost_max(), 0.5e-3, 1e-15);
  feed(g, 250, quiet);
  EXPECT_EQ(g.steps_one(), 11);
  EXPECT_EQ(g.steps_max(), 10 + 11 + 250);
  EXPECT_EQ(g.threads(), 2);
}

TEST(ThreadGovernor, TheFirstCostOfTwoThreadsIsNoConfirmingProbe) {
  // no room after the first block, room from then on; two threads 3x
  // dearer. Their first timed block (a probe right after one one-thread
  // block) measures them: it loses the first comparison, so they are
  // rechecked after ceil(15 x 3 / 8) = 6 blocks; neither doubles the
  // spacing, so the next probe comes 15 x 3 = 45 blocks later (with the
  // doubling: 90 or 180), then 90
  ThreadGovernor g(2, 10, 0.0, 15);
  int asked = 0;
  g.set_room_check([&](int) { return ++asked > 1; });
  const auto loaded = [](int t) { return t == 1 ? 1e-3 : 3e-3; };
  feed(g, 10 + 11, loaded);  // the first block, one one-thread block
  ASSERT_EQ(g.threads(), 2);
  ASSERT_EQ(g.cost_max(), 0.0);
  const std::vector<std::int64_t> gaps = probe_gaps(g, loaded, 1, 3, 4000, true);
  ASSERT_EQ(gaps.size(), 3u);
  EXPECT_NEAR(g.cost_max(), 3e-3, 1e-15);
  // each gap holds the first step after the switch back (untimed)
  EXPECT_EQ(gaps[0], 10 * 6 + 1);
  EXPECT_EQ(gaps[1], 10 * 45 + 1);
  EXPECT_EQ(gaps[2], 10 * 90 + 1);
}

TEST(ThreadGovernor, NoProbeOfMoreThreadsWhileTheOtherCoresAreBusy) {
  ThreadGovernor g(2, 10, 0.0, 15);
  bool room = true;
  int asked = 0;
  g.set_room_check([&](int) {
    ++asked;
    return room;
  });
  // the start with room (asked at the end of the untimed block): a timed
  // block on two threads, then one thread; two threads 3x dearer (the load
  // came after the start)
  const auto loaded = [](int t) { return t == 1 ? 1e-3 : 3e-3; };
  feed(g, 10 + 10 + 11, loaded);
  ASSERT_EQ(g.threads(), 1);
  ASSERT_EQ(asked, 1);
  const std::int64_t max_before = g.steps_max();
  // no room: the recheck of two threads (they lost the start) due after
  // ceil(15 x 3 / 8) = 6 blocks (the start's one-thread block is the
  // first: block 5 of these 2000) is not run; the room is asked then and
  // after 1, 2, 4, 8 and then every 15 blocks: at blocks 5, 6, 8, 12, 20,
  // 35, 50, .. 2000
  room = false;
  feed(g, 20000, loaded);
  EXPECT_EQ(g.steps_max(), max_before);  // with room: probes after 6, 45, 90, 180 .. blocks
  EXPECT_EQ(asked, 1 + 5 + (2000 - 20) / 15);
  // room again: two threads are probed within 15 blocks
  room = true;
  const std::int64_t one_before = g.steps_one();
  while (g.threads() == 1 && g.steps_one() - one_before <= 200) g.record_step(loaded(1));
  EXPECT_LE(g.steps_one() - one_before, 150);
  EXPECT_EQ(g.threads(), 2);
}

TEST(ThreadGovernor, TheRunsFirstBlockIsNotTimed) {
  ThreadGovernor g(2, 10, 0.0, 15);
  // the start makes the first block of two threads 2x dearer than two
  // threads are (which are 1.6x cheaper than one)
  feed(g, 10, [](int) { return 2e-3; });
  EXPECT_EQ(g.threads(), 2);
  EXPECT_EQ(g.cost_max(), 0.0);
  // the start blocks (two threads, one thread), then 20 blocks: fewer than
  // the 15 x 1.6 before the next probe
  feed(g, 10 + 11 + 200, [](int t) { return t == 1 ? 1.6e-3 : 1e-3; });
  EXPECT_NEAR(g.cost_max(), 1e-3, 1e-15);
  EXPECT_NEAR(g.cost_one(), 1.6e-3, 1e-15);
  // one thread ran its start probe only (11 steps: the first after the
  // change untimed); timed, the first block (2e-3) would have made one
  // thread the cheaper count and run it for 15 x 1.25 blocks
  EXPECT_EQ(g.steps_one(), 11);
  EXPECT_EQ(g.threads(), 2);
}

TEST(ThreadGovernor, OneSlowBlockDoesNotFlipTheCountTwoDo) {
  ThreadGovernor g(2, 10, 0.0, 15);
  // two threads 1.2x cheaper; the untimed first block, then three blocks:
  // two threads, one thread, two threads (10 steps each, and the first step
  // after each change untimed)
  feed(g, 10 + 10 + 11 + 11, [](int t) { return t == 1 ? 1.2e-3 : 1e-3; });
  EXPECT_EQ(g.steps_max(), 31);
  ASSERT_EQ(g.threads(), 2);
  // one block of two threads slowed to 1.5e-3 (a hiccup of the host)
  feed(g, 10, [](int) { return 1.5e-3; });
  EXPECT_EQ(g.threads(), 2);
  EXPECT_NEAR(g.cost_max(), 1e-3, 1e-15);  // the lower of the last two blocks
  // the slowdown lasts: the second slow block shows it
  feed(g, 10, [](int) { return 1.5e-3; });
  EXPECT_NEAR(g.cost_max(), 1.5e-3, 1e-15);
  EXPECT_EQ(g.threads(), 1);
}

TEST(ThreadGovernor, AProbeBlockGivesItsOwnCost) {
  ThreadGovernor g(2, 10, 0.0, 2, 64.0);  // a probe after 2 r blocks
  // start: the untimed first block, two threads 1e-3, one thread 1.2e-3
  // (two blocks), then two threads
  feed(g, 10 + 10 + 11 + 11, [](int t) { return t == 1 ? 1.2e-3 : 1e-3; });
  ASSERT_EQ(g.threads(), 2);
  // one thread gets 40x dearer: its next probe block alone sets its cost
  // (not the lower of it and the older, cheap block)
  const std::int64_t one_before = g.steps_one();
  while (g.steps_one() == one_before) feed(g, 1, [](int t) { return t == 1 ? 48e-3 : 1e-3; });
  feed(g, 10, [](int t) { return t == 1 ? 48e-3 : 1e-3; });
  EXPECT_NEAR(g.cost_one(), 48e-3, 1e-15);
  EXPECT_EQ(g.threads(), 2);
}

TEST(ThreadGovernor, StepsWhoseCostIsNotTheCountsAreCountedNotTimed) {
  ThreadGovernor g(2, 10, 0.0, 15);
  feed(g, 10, [](int) { return 1.0; });  // the run's first block: not timed
  EXPECT_EQ(g.cost_max(), 0.0);
  // a block of two threads: 10 timed steps of 1e-3 s and 3 list rebuilds of 1 s
  for (int k = 0; k < 10; ++k) {
    g.record_step(1e-3);
    if (k % 4 == 0) g.record_step(1.0, false);
  }
  EXPECT_EQ(g.steps_max(), 23);
  EXPECT_NEAR(g.cost_max(), 1e-3, 1e-15);
  ASSERT_EQ(g.threads(), 1);  // start: now one thread
  // the first step after the change of count (plans remade) is not timed either
  g.record_step(5.0);
  for (int k = 0; k < 10; ++k) g.record_step(2e-3);
  EXPECT_EQ(g.steps_one(), 11);
  EXPECT_NEAR(g.cost_one(), 2e-3, 1e-15);
  EXPECT_EQ(g.threads(), 2);
  // every step rebuilds the list: after kMaxUntimed x 10 untimed steps the
  // block times what it gets, so it still ends
  ThreadGovernor busy(2, 10, 0.0, 15);
  for (int k = 0; k < 10 + ThreadGovernor::kMaxUntimed * 10 + 10; ++k) busy.record_step(3e-3, false);
  EXPECT_EQ(busy.threads(), 1);
  EXPECT_NEAR(busy.cost_max(), 3e-3, 1e-15);
}

TEST(ThreadGovernor, BlocksSpanTheMinimumWallTime) {
  ThreadGovernor g(2, 1, 0.05, 15);
  feed(g, 9, [](int) { return 0.006; });  // 54 ms: the untimed first block
  EXPECT_EQ(g.threads(), 2);
  EXPECT_EQ(g.cost_max(), 0.0);
  feed(g, 8, [](int) { return 0.006; });  // 48 ms: still the first timed block
  EXPECT_EQ(g.threads(), 2);
  feed(g, 1, [](int) { return 0.006; });
  EXPECT_EQ(g.threads(), 1);
  ThreadGovernor single(1);
  feed(single, 100, [](int) { return 1.0; });
  EXPECT_EQ(single.threads(), 1);
  EXPECT_EQ(single.steps_one() + single.steps_max(), 0);
}

TEST(ThreadGovernor, SwitchingCountsKeepsTheRunBitIdentical) {
  // 2100 particles: 5 chunks, enough for two threads (useful_threads)
  vt::test::CloudScene sc = vt::test::polydisperse_cloud(2100, 0.9, 11);
  SimulationSettings s = vt::test::undamped(0.3);
  s.damping = MassDamping(DampingModel::OD, 0.05);
  Simulation one(sc.particles, sc.cell, s), governed(sc.particles, sc.cell, s);
  const double rate = 2e-4 / one.time_scale().t0;
  one.set_strain_rates({-rate, -rate, -rate});
  governed.set_strain_rates({-rate, -rate, -rate});
  // switch every few steps whatever the timings (probe spacing 1, 2 or 4 blocks)
  governed.set_thread_governor(ThreadGovernor(2, 3, 0.0, 1, 1.0));
  omp_set_num_threads(1);
  ASSERT_EQ(one.run(600), 600);
  ASSERT_EQ(governed.run(600), 600);
  omp_set_num_threads(1);
  EXPECT_GT(governed.thread_governor()->steps_one(), 100);
  EXPECT_GT(governed.thread_governor()->steps_max(), 100);
  const auto& a = one.particles();
  const auto& b = governed.particles();
  EXPECT_EQ(std::memcmp(a.frac.data(), b.frac.data(), a.size() * sizeof(Vec3)), 0);
  EXPECT_EQ(std::memcmp(a.velocity.data(), b.velocity.data(), a.size() * sizeof(Vec3)), 0);
  EXPECT_EQ(std::memcmp(a.omega.data(), b.omega.data(), a.size() * sizeof(Vec3)), 0);
}

TEST(ThreadGovernor, CapsTheCountToTheSpecimensChunks) {
  // at least kMinChunksPerThread = 2 chunks of 512 particles per thread
  EXPECT_EQ(ThreadGovernor::useful_threads(0, 2), 1);
  EXPECT_EQ(ThreadGovernor::useful_threads(2, 2), 1);
  EXPECT_EQ(ThreadGovernor::useful_threads(3, 2), 1);
  EXPECT_EQ(ThreadGovernor::useful_threads(4, 2), 2);
  EXPECT_EQ(ThreadGovernor::useful_threads(24, 2), 2);
  EXPECT_EQ(ThreadGovernor::useful_threads(5, 4), 2);
  EXPECT_EQ(ThreadGovernor::useful_threads(8, 4), 4);
  EXPECT_EQ(ThreadGovernor::useful_threads(8, 1), 1);
  // a cap that lowers the maximum starts afresh (no cost of the old maximum kept)
  ThreadGovernor g(2, 1, 0.0, 15);
  for (int k = 0; k < 5; ++k) g.record_step(1e-3);
  ASSERT_GT(g.steps_max() + g.steps_one(), 0);
  ASSERT_GT(g.cost_max(), 0.0);
  g.limit_to_chunks(3);
  EXPECT_EQ(g.max_threads(), 1);
  EXPECT_EQ(g.threads(), 1);
  EXPECT_EQ(g.steps_max() + g.steps_one(), 0);
  EXPECT_EQ(g.cost_max(), 0.0);
  g.limit_to_chunks(40);  // never raised
  EXPECT_EQ(g.max_threads(), 1);

  // a 1000-particle specimen (2 chunks) runs on one thread: no probe block on two
  const SimulationSettings s = vt::test::undamped(0.3);
  vt::test::CloudScene small = vt::test::polydisperse_cloud(1000, 0.9, 3);
  Simulation a(small.particles, small.cell, s);
  a.set_thread_governor(ThreadGovernor(2, 3, 0.0, 1, 1.0));
  EXPECT_EQ(a.thread_governor()->max_threads(), 1);
  omp_set_num_threads(2);
  ASSERT_EQ(a.run(60), 60);
  EXPECT_EQ(omp_get_max_threads(), 2);  // the caller's count is restored after each step
  EXPECT_FALSE(a.split_used());          // the step itself ran one thread
  EXPECT_EQ(a.thread_governor()->steps_max(), 0);
  // 2100 particles (5 chunks): two threads stay a candidate and are probed
  vt::test::CloudScene large = vt::test::polydisperse_cloud(2100, 0.9, 3);
  Simulation b(large.particles, large.cell, s);
  b.set_thread_governor(ThreadGovernor(2, 3, 0.0, 1, 1.0));
  EXPECT_EQ(b.thread_governor()->max_threads(), 2);
  ASSERT_EQ(b.run(60), 60);
  omp_set_num_threads(1);
  EXPECT_GT(b.thread_governor()->steps_max(), 0);
  EXPECT_GT(b.thread_governor()->steps_one(), 0);
}

TEST(ThreadGovernor, TheBlockLogSaysWhatEachBlockRanAndChose) {
  // four threads capped to two by the chunks (the governor starts afresh):
  // the log is kept
  ThreadGovernor g(4, 10, 0.0, 2, 64.0);  // a probe after 2 r blocks
  std::vector<ThreadGovernor::Block> log;
  g.set_block_log([&log](const ThreadGovernor::Block& b) { log.push_back(b); });
  g.limit_to_chunks(4);
  ASSERT_EQ(g.max_threads(), 2);
  // the untimed start, two threads (1e-3) with one list rebuild, one thread
  // (1.5e-3), then two threads until a probe of one thread has ended
  g.record_step(4e-3);
  feed(g, 9, [](int) { return 4e-3; });
  g.record_step(9.0, false);
  feed(g, 10, [](int t) { return t == 1 ? 1.5e-3 : 1e-3; });
  feed(g, 11, [](int t) { return t == 1 ? 1.5e-3 : 1e-3; });
  for (int k = 0; k < 1000 && (log.size() < 4 || !log.back().probe); ++k)
    feed(g, 1, [](int t) { return t == 1 ? 1.5e-3 : 1e-3; });
  ASSERT_TRUE(!log.empty() && log.back().probe) << "no probe within 1000 steps";
  EXPECT_TRUE(log[0].start);
  EXPECT_EQ(log[0].threads, 2);
  EXPECT_EQ(log[0].untimed_steps, 10);
  EXPECT_NEAR(log[0].seconds_per_step, 4e-3, 1e-15);
  EXPECT_EQ(log[0].next, 2);
  EXPECT_FALSE(log[1].start || log[1].probe);
  EXPECT_EQ(log[1].end_step, 21);  // the rebuild counted, not timed
  EXPECT_EQ(log[1].timed_steps, 10);
  EXPECT_EQ(log[1].untimed_steps, 1);
  EXPECT_NEAR(log[1].seconds_per_step, 1e-3, 1e-15);
  EXPECT_NEAR(log[1].cost_max, 1e-3, 1e-15);
  EXPECT_EQ(log[1].cost_one, 0.0);
  EXPECT_EQ(log[1].next, 1);
  EXPECT_EQ(log[2].threads, 1);
  EXPECT_EQ(log[2].untimed_steps, 1);  // the first step after the switch
  EXPECT_NEAR(log[2].cost_one, 1.5e-3, 1e-15);
  EXPECT_EQ(log[2].next, 2);
  // the probe: one thread after ceil(2 x 1.5) = 3 blocks of two threads
  const ThreadGovernor::Block& probe = log.back();
  EXPECT_EQ(log.size(), 3u + 3u + 1u);
  EXPECT_EQ(probe.threads, 1);
  EXPECT_EQ(probe.next, 2);
  for (std::size_t k = 1; k < log.size(); ++k) {
    EXPECT_EQ(log[k].threads, log[k - 1].next) << "block " << k;
    EXPECT_EQ(log[k].end_step - log[k - 1].end_step, log[k].timed_steps + log[k].untimed_steps) << "block " << k;
  }
  EXPECT_EQ(probe.end_step, g.steps_one() + g.steps_max());
}

TEST(ThreadGovernor, AStartLostByTwoThreadsIsRecheckedSoon) {
  // the start's transients make the first timed block of two threads 1.1x
  // dearer than one thread, though two threads then cost 0.75 of one: the
  // recheck after ceil(15 x 1.1 / 8) = 3 blocks (the start's one-thread
  // block the first) finds it, not the probe after ceil(15 x 1.1) = 17
  ThreadGovernor g(2, 10, 0.0, 15);
  feed(g, 10, [](int) { return 5e-3; });         // the untimed first block
  feed(g, 10, [](int) { return 1.1e-3; });       // two threads, start transients
  ASSERT_EQ(g.threads(), 1);
  const auto settled = [](int t) { return t == 1 ? 1e-3 : 0.75e-3; };
  const std::vector<std::int64_t> gaps = probe_gaps(g, settled, 1, 1, 1000, true);
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0], 11 + 2 * 10);
  feed(g, 11, settled);  // the recheck block: two threads win
  EXPECT_EQ(g.threads(), 2);
  EXPECT_NEAR(g.cost_max(), 0.75e-3, 1e-15);
  // a start won by two threads (half the cost of one) has no recheck: one
  // thread is probed after 15 x 2 = 30 two-thread blocks (the first step
  // after the start's one-thread block untimed)
  const double unit = 1.0 / 1024;  // exact ratios
  const auto halved = [&](int t) { return t == 1 ? unit : 0.5 * unit; };
  ThreadGovernor won(2, 10, 0.0, 15);
  feed(won, 10, [](int) { return 5e-3; });
  feed(won, 10 + 11, halved);  // the start's blocks: two threads, one thread
  ASSERT_EQ(won.threads(), 2);
  const std::vector<std::int64_t> twos = probe_gaps(won, halved, 2, 1, 1000, true);
  ASSERT_EQ(twos.size(), 1u);
  EXPECT_EQ(twos[0], 11 + 29 * 10);
}
