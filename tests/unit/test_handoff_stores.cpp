// HandoffStores (dem/handoff_stores.h): how the integrator stores the chunks
// whose particles another thread's pair loop reads, and streaming_copy
// (dem/streaming_copy.h), which streams them.
//   - the choice: Auto streams after a plain window in which a particle of a
//     shared chunk cost more than kSlowRatio times one of the others (the
//     slowest thread's ratio), measures again after kProbeWindows streamed
//     windows, and stays plain below the threshold; Plain and Streaming
//     hold;
//   - streaming_copy copies every value bit for bit at every alignment and
//     length and writes nothing outside the destination;
//   - on a team, the streamed stores and the plain ones give the one-thread
//     run bit for bit; streaming takes some chunks but not all, and a
//     plain run times shared and other chunks.
#include <gtest/gtest.h>

#include <omp.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "support/omp_threads.h"
#include "support/scenes.h"
#include "support/state_compare.h"
#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/dem/handoff_stores.h"
#include "virtual_triaxial/dem/periodic_tiling.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/dem/streaming_copy.h"

using namespace vt::dem;

namespace {

/// One window of steps on two threads in which a particle of a shared
/// chunk costs `ratio0` (thread 0) and `ratio1` (thread 1) times one of the
/// other chunks; returns whether the stores stream after it.
bool window(HandoffStores& h, double ratio0, double ratio1) {
  for (int s = 0; s < HandoffStores::kWindowSteps; ++s) {
    if (!h.streaming()) {
      h.record(0, true, 100 * 1e-8 * ratio0, 100);  // 100 particles at 1e-8 s x ratio
      h.record(0, false, 400 * 1e-8, 400);
      h.record(1, true, 50 * 2e-8 * ratio1, 50);
      h.record(1, false, 300 * 2e-8, 300);
    }
    h.end_step();
  }
  return h.streaming();
}

}  // namespace

TEST(HandoffStores, AutoStreamsWhileTheSharedChunksCostMoreAndMeasuresAgain) {
  HandoffStores h;
  h.ensure_threads(2);
  ASSERT_EQ(h.mode(), HandoffStores::Mode::Auto);
  EXPECT_FALSE(h.streaming()) << "plain until a window has been measured";
  // the slower thread decides: thread 1 at 4x, thread 0 near
  EXPECT_TRUE(window(h, 1.2, 4.0));
  EXPECT_NEAR(h.last_ratio(), 4.0, 1e-9);
  // streamed windows are not measured: kProbeWindows of them, then one plain
  for (int w = 1; w < HandoffStores::kProbeWindows; ++w) ASSERT_TRUE(window(h, 1.0, 1.0)) << "window " << w;
  EXPECT_FALSE(window(h, 1.0, 1.0)) << "after kProbeWindows streamed windows, a plain one to measure";
  EXPECT_EQ(h.streamed_steps(), std::int64_t{HandoffStores::kProbeWindows} * HandoffStores::kWindowSteps);
  // the probe finds the lines cheap again: plain
  EXPECT_FALSE(window(h, 1.3, 1.1));
  EXPECT_NEAR(h.last_ratio(), 1.3, 1e-9);
  EXPECT_FALSE(window(h, 1.3, 1.1));
  EXPECT_EQ(h.steps(), std::int64_t{HandoffStores::kProbeWindows + 3} * HandoffStores::kWindowSteps);
}

TEST(HandoffStores, TheThresholdIsTheSlowRatio) {
  HandoffStores below, above;
  below.ensure_threads(2);
  above.ensure_threads(2);
  EXPECT_FALSE(window(below, 0.98 * HandoffStores::kSlowRatio, 1.0));
  EXPECT_TRUE(window(above, 1.0, 1.02 * HandoffStores::kSlowRatio));
  // a thread without other chunks (all its chunks shared) does not count
  HandoffStores lone;
  lone.ensure_threads(1);
  for (int s = 0; s < HandoffStores::kWindowSteps; ++s) {
    lone.record(0, true, 1.0, 10);
    lone.end_step();
  }
  EXPECT_FALSE(lone.streaming());
  EXPECT_EQ(lone.last_ratio(), 0.0);
}

TEST(HandoffStores, ForcedModesHold) {
  HandoffStores plain, streaming;
  plain.ensure_threads(2);
  streaming.ensure_threads(2);
  plain.set_mode(HandoffStores::Mode::Plain);
  streaming.set_mode(HandoffStores::Mode::Streaming);
  EXPECT_TRUE(streaming.streaming());
  for (int w = 0; w < HandoffStores::kProbeWindows + 2; ++w) {
    ASSERT_FALSE(window(plain, 10.0, 10.0)) << "plain stays plain, window " << w;
    ASSERT_TRUE(window(streaming, 1.0, 1.0)) << "streaming stays streaming, window " << w;
  }
  EXPECT_NEAR(plain.last_ratio(), 10.0, 1e-9) << "a plain run still measures the ratio";
  EXPECT_EQ(plain.streamed_steps(), 0);
  EXPECT_EQ(streaming.streamed_steps(), streaming.steps());
}

TEST(StreamingCopy, CopiesEveryValueAtEveryAlignmentAndNothingElse) {
  constexpr std::size_t kRoom = 64;
  std::vector<Vec3> src(kRoom), dst(kRoom + 8);
  for (std::size_t k = 0; k < kRoom; ++k) src[k] = Vec3{1.0 + k, -0.5 * k, 1e-300 * (k + 1)};
  const Vec3 guard{-7.0, 7.0, 3.25};
  // destinations at every offset of 8 Vec3 (24-byte steps through the 64-byte lines)
  for (std::size_t offset = 0; offset < 8; ++offset) {
    for (std::size_t count = 0; count <= 40; ++count) {
      for (Vec3& v : dst) v = guard;
      streaming_copy(dst.data() + offset, src.data(), count);
      streaming_fence();
      for (std::size_t k = 0; k < dst.size(); ++k) {
        const bool inside = k >= offset && k < offset + count;
        const Vec3& want = inside ? src[k - offset] : guard;
        ASSERT_EQ(std::memcmp(&dst[k], &want, sizeof(Vec3)), 0)
            << "offset " << offset << ", count " << count << ", slot " << k << (inside ? " (copied)" : " (outside)");
      }
    }
  }
}

namespace {

/// A loaded, sorted packing of 1603 x 3 = 4809 spheres: 10 chunks, the last
/// one partial (and not a whole number of the integrator's lane groups),
/// so each of two threads' runs has chunks that the other thread reads and
/// chunks it does not.
SimulationState three_tiles() {
  return vt::test::spatially_sorted(tile_periodic(vt::test::loaded_packing(1603), 3, 1, 1));
}

}  // namespace

TEST(HandoffStores, StreamedAndPlainStoresGiveTheOneThreadBits) {
  const vt::test::RestoreThreads restore;
  const SimulationState start = three_tiles();
  const std::int64_t chunks = chunk_count(start.particles.size());
  ASSERT_NE(start.particles.size() % 8, 0u) << "the test needs a partial lane group";
  omp_set_num_threads(1);
  Simulation one(start);
  ASSERT_EQ(one.run(120), 120) << one.failure();
  EXPECT_EQ(one.handoff_stores().steps(), 0) << "one thread: no handoff";
  omp_set_num_threads(2);
  for (const HandoffStores::Mode mode : {HandoffStores::Mode::Streaming, HandoffStores::Mode::Plain}) {
    Simulation two(start);
    two.handoff_stores().set_mode(mode);
    ASSERT_EQ(two.run(120), 120) << two.failure();
    ASSERT_TRUE(two.split_used());
    EXPECT_EQ(two.handoff_stores().steps(), 120);
    const std::int64_t streamed = two.handoff_stores().streamed_chunks();
    if (mode == HandoffStores::Mode::Streaming) {
      EXPECT_EQ(two.handoff_stores().streamed_steps(), 120);
      EXPECT_GE(streamed, 2 * 120) << "at least one chunk per thread and step streamed";
      EXPECT_LT(streamed, 120 * chunks) << "the inner chunks stored plainly";
    } else {
      EXPECT_EQ(two.handoff_stores().streamed_steps(), 0);
      EXPECT_EQ(streamed, 0);
      EXPECT_GT(two.handoff_stores().last_ratio(), 0.0) << "the plain stores timed shared and other chunks";
    }
    vt::test::expect_same_state(one.state(), two.state());
  }
}
