// protocol/checkpoint_schedule.h: when a checkpoint inside a stage is due,
// the one rule of both runners (StageRunner headless, ProtocolSession on the
// rig): off when both triggers are 0; after `every_ticks` ticks; never
// sooner than kCheckpointCostFactor x the last checkpoint's cost, even when
// the tick trigger is met; the count starts again after each checkpoint.
#include <gtest/gtest.h>

#include "virtual_triaxial/protocol/checkpoint_schedule.h"

using vt::protocol::CheckpointSchedule;
using vt::protocol::kCheckpointCostFactor;

TEST(CheckpointSchedule, OffWhenBothTriggersAreZero) {
  CheckpointSchedule s(0, 0.0);
  EXPECT_FALSE(s.enabled());
  for (int i = 0; i < 1000; ++i) s.tick();
  EXPECT_FALSE(s.due());
}

TEST(CheckpointSchedule, DueAfterTheTickCountAndCountingAgainAfterEachCheckpoint) {
  CheckpointSchedule s(100, 0.0);
  ASSERT_TRUE(s.enabled());
  for (int i = 0; i < 99; ++i) s.tick();
  EXPECT_FALSE(s.due()) << "99 of 100 ticks";
  s.tick();
  EXPECT_TRUE(s.due());
  s.tick();
  EXPECT_TRUE(s.due()) << "stays due until a checkpoint is taken (the next sample tick)";
  s.done(0.0);
  EXPECT_FALSE(s.due()) << "counting starts again";
  for (int i = 0; i < 100; ++i) s.tick();
  EXPECT_TRUE(s.due());
}

TEST(CheckpointSchedule, TheCostBoundHoldsBackACheckpointThatTheTicksAskFor) {
  // The last checkpoint took 2 s: the next one not within 20 x 2 = 40 s,
  // whatever the tick count says (this test runs in far less).
  ASSERT_EQ(kCheckpointCostFactor, 20.0);
  CheckpointSchedule s(1, 0.0);
  s.tick();
  ASSERT_TRUE(s.due());
  s.done(2.0);
  for (int i = 0; i < 1000; ++i) s.tick();
  EXPECT_FALSE(s.due());
  s.restart();  // a new run: no cost remembered
  s.tick();
  EXPECT_TRUE(s.due());
}

TEST(CheckpointSchedule, TheSecondsTriggerWaitsForItsTime) {
  CheckpointSchedule s(0, 3600.0);
  ASSERT_TRUE(s.enabled());
  for (int i = 0; i < 1000; ++i) s.tick();
  EXPECT_FALSE(s.due()) << "an hour has not passed";
}
