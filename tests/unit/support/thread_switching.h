// Thread counts switched mid-run, as the run-time governor does
// (dem/thread_governor.h): the run must be the one-thread run bit for bit.
#pragma once

#include <gtest/gtest.h>
#include <omp.h>

#include <cstdint>

#include "support/omp_threads.h"
#include "support/state_compare.h"
#include "virtual_triaxial/dem/simulation.h"

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

}  // namespace vt::test
