// ThreadRuns (dem/thread_runs.h): runs of chunks per thread, re-cut by
// measured speed. Invariants: the runs tile [0, chunks) in thread order
// without an empty run; a thread measured k times slower gets about 1/k of
// the share of a fast one; noise below kMinGain leaves the cut alone.
#include <gtest/gtest.h>

#include <cstdint>

#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/dem/thread_runs.h"

using vt::dem::kChunkSize;
using vt::dem::ThreadRuns;

namespace {

void expect_tiling(const ThreadRuns& r) {
  std::int32_t next = 0;
  for (int t = 0; t < r.threads(); ++t) {
    const auto [c0, c1] = r.run(t);
    EXPECT_EQ(c0, next) << "thread " << t;
    EXPECT_GT(c1, c0) << "thread " << t << " has no chunk";
    next = c1;
  }
  EXPECT_EQ(next, r.chunks());
}

std::size_t particles(const ThreadRuns& r, int t, std::size_t n) {
  const auto [c0, c1] = r.run(t);
  const std::size_t hi = std::min(n, static_cast<std::size_t>(c1) * kChunkSize);
  return hi - static_cast<std::size_t>(c0) * kChunkSize;
}

/// One window of steps in which thread t takes seconds_per_particle[t] per
/// particle of its run.
void window(ThreadRuns& r, std::size_t n, const std::vector<double>& seconds_per_particle) {
  for (int s = 0; s < ThreadRuns::kWindowSteps; ++s) {
    for (int t = 0; t < r.threads(); ++t)
      r.record(t, seconds_per_particle[static_cast<std::size_t>(t)] * static_cast<double>(particles(r, t, n)));
    r.end_step();
  }
}

}  // namespace

TEST(ThreadRuns, StartEqualAndTileTheChunks) {
  ThreadRuns r;
  const std::size_t n = 100000;
  r.prepare(vt::dem::chunk_count(n), n, 2);
  expect_tiling(r);
  EXPECT_EQ(r.run(0), vt::dem::chunk_run(r.chunks(), 0, 2));
  const std::int64_t v = r.version();
  r.prepare(vt::dem::chunk_count(n), n, 2);  // unchanged: kept
  EXPECT_EQ(r.version(), v);
  r.prepare(vt::dem::chunk_count(n), n, 3);
  EXPECT_NE(r.version(), v);
  expect_tiling(r);
}

TEST(ThreadRuns, ASlowerThreadGetsAShareInProportionToItsSpeed) {
  ThreadRuns r;
  const std::size_t n = 100000;  // 196 chunks
  r.prepare(vt::dem::chunk_count(n), n, 2);
  // thread 0 twice as slow per particle: shares 1/3 and 2/3 equalise the times
  window(r, n, {2e-7, 1e-7});
  EXPECT_EQ(r.recuts(), 1);
  expect_tiling(r);
  const double share0 = static_cast<double>(particles(r, 0, n)) / static_cast<double>(n);
  EXPECT_NEAR(share0, 1.0 / 3.0, 0.5 * kChunkSize / static_cast<double>(n) + 1e-12);
  // Times now equal within a chunk: a second window keeps the cut.
  const std::int64_t v = r.version();
  window(r, n, {2e-7, 1e-7});
  EXPECT_EQ(r.version(), v);
}

TEST(ThreadRuns, NoiseBelowTheMinimumGainKeepsTheCut) {
  ThreadRuns r;
  const std::size_t n = 100000;
  r.prepare(vt::dem::chunk_count(n), n, 2);
  const std::int64_t v = r.version();
  // 2 % slower: the best cut would gain under 1 %, less than kMinGain
  window(r, n, {1.02e-7, 1e-7});
  EXPECT_EQ(r.version(), v);
  EXPECT_EQ(r.recuts(), 0);
}

TEST(ThreadRuns, AWindowNeedsEnoughStepsAndWork) {
  ThreadRuns r;
  const std::size_t n = 100000;
  r.prepare(vt::dem::chunk_count(n), n, 2);
  // 4x slower thread, but too little work per window to judge: no re-cut
  for (int s = 0; s < 10 * ThreadRuns::kWindowSteps; ++s) {
    r.record(0, 1e-7);
    r.record(1, 0.25e-7);
    r.end_step();
  }
  EXPECT_EQ(r.recuts(), 0);
}

TEST(ThreadRuns, EveryThreadKeepsAChunkWhenOneIsFarSlower) {
  ThreadRuns r;
  const std::size_t n = 5000;  // 10 chunks, 4 threads
  r.prepare(vt::dem::chunk_count(n), n, 4);
  window(r, n, {1e-3, 1e-6, 1e-6, 1e-6});
  expect_tiling(r);
  EXPECT_EQ(r.run(0).second - r.run(0).first, 1);
}
