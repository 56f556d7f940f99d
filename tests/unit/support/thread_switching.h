// Thread counts switched mid-run, as the run-time governor does
// (dem/thread_governor.h), and the threads' runs re-cut mid-run, as a
// thread that turns slower makes them (dem/thread_runs.h): the run must be
// the one-thread run bit for bit.
#pragma once

#include <gtest/gtest.h>
#include <omp.h>

#include <cstdint>

#include "support/omp_threads.h"
#include "support/state_compare.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/dem/thread_runs.h"

namespace vt::test {

/// `start` run `each` steps at a time on 2, 1, 2, 3, 1, 3, 2 threads (back
/// to a count whose runs and plan are kept after one-thread steps, so the
/// threads' ghost copies must be taken from the list again, split_sums.h)
/// against as many steps on one thread: the two states agree bit for bit.
inline void expect_switching_threads_keeps_the_bits(const dem::SimulationState& start, std::int64_t each) {
  const int counts[] = {2, 1, 2, 3, 1, 3, 2};
  RestoreThreads restore;
  omp_set_num_threads(1);
  dem::Simulation one(start);
  const std::int64_t total = each * static_cast<std::int64_t>(sizeof counts / sizeof counts[0]);
  ASSERT_EQ(one.run(total), total) << one.failure();
  dem::Simulation switched(start);
  for (const int threads : counts) {
    omp_set_num_threads(threads);
    ASSERT_EQ(switched.run(each), each) << switched.failure();
    EXPECT_EQ(switched.split_used(), threads > 1);
  }
  expect_same_state(one.state(), switched.state());
}

/// `start` on two threads whose runs are re-cut `windows` times: before
/// each window of ThreadRuns::kWindowSteps steps one thread (0, 1, 0, ..)
/// is made to look a second busier, so the window's end moves chunks off
/// it. Between the re-cuts the threads' ghost copies carry their state
/// from step to step (split_sums.h); at each re-cut the plan and the ghosts
/// are made again. Against as many steps on one thread: bit for bit.
inline void expect_recuts_keep_the_bits(const dem::SimulationState& start, int windows) {
  RestoreThreads restore;
  const std::int64_t each = dem::ThreadRuns::kWindowSteps;
  const std::int64_t total = 1 + each * windows;
  omp_set_num_threads(1);
  dem::Simulation one(start);
  ASSERT_EQ(one.run(total), total) << one.failure();
  omp_set_num_threads(2);
  dem::Simulation cut(start);
  ASSERT_EQ(cut.run(1), 1) << cut.failure();  // the plan: equal runs
  ASSERT_TRUE(cut.split_used());
  ASSERT_GE(cut.thread_runs().chunks(), 4) << "the test needs room to move the cut";
  for (int w = 0; w < windows; ++w) {
    const std::int64_t version = cut.thread_runs().version();
    const auto before = cut.thread_runs().run(w % 2);
    cut.thread_runs().record(w % 2, 1.0);
    ASSERT_EQ(cut.run(each), each) << cut.failure();
    EXPECT_NE(cut.thread_runs().version(), version) << "window " << w << ": no re-cut";
    const auto after = cut.thread_runs().run(w % 2);
    EXPECT_LT(after.second - after.first, before.second - before.first) << "window " << w;
  }
  EXPECT_EQ(cut.thread_runs().recuts(), windows);
  expect_same_state(one.state(), cut.state());
}

}  // namespace vt::test
