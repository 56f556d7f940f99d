// Node-layer logic without a master: AxisArbiter (axis ownership, open-loop
// rates, lockstep bookkeeping, refusals naming the field) and TargetRamp.
#include <cmath>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "virtual_triaxial/ros/axis_arbiter.h"
#include "virtual_triaxial/ros/target_ramp.h"

using vt::ros::AxisArbiter;
using vt::ros::TargetRamp;

namespace {

bool starts_with(const std::string& s, const std::string& p) { return s.compare(0, p.size(), p) == 0; }

AxisArbiter make() {
  AxisArbiter a;
  a.set_limit(1e-6, 1e-3);  // T0 = 1 us: |rate| <= 1000 1/s
  return a;
}

}  // namespace

TEST(AxisArbiter, ClaimsAreExclusiveAllOrNothingAndReleasable) {
  AxisArbiter a = make();
  EXPECT_EQ(a.claim("servo", {0, 1}, 0), "");
  EXPECT_EQ(a.claim("servo", {0}, 0), "") << "re-claiming one's own axis is a no-op";
  const std::string bad = a.claim("other", {2, 1}, 0);
  EXPECT_TRUE(starts_with(bad, "axes:")) << bad;
  EXPECT_NE(bad.find("'servo'"), std::string::npos) << bad;
  EXPECT_EQ(a.owner(2), "") << "a refused claim must not take any axis";
  EXPECT_TRUE(starts_with(a.claim("", {2}, 0), "owner:"));
  EXPECT_TRUE(starts_with(a.claim("x", {3}, 0), "axes:"));
  EXPECT_TRUE(starts_with(a.release("other", {0}), "owner:"));
  EXPECT_EQ(a.claim("other", {2}, 0), "");
  EXPECT_TRUE(starts_with(a.release("other", {0}), "axes:"));
  EXPECT_EQ(a.release("servo", {}), "");
  EXPECT_EQ(a.owner(0), "");
  EXPECT_EQ(a.owner(1), "");
  EXPECT_EQ(a.claim("other", {0}, 0), "") << "a released axis is free";
}

TEST(AxisArbiter, AClaimMadeAgainKeepsTheTickOfTheFirstClaim) {
  // A controller whose claim's answer was lost (ros/ros_comm#1976) claims
  // again a tick later: dem_node still waits on it from the first claim on,
  // and claimed_at / answer_tick (what claim_axes answers) must say so.
  AxisArbiter a = make();
  EXPECT_FALSE(a.claimed_at("servo").has_value());
  ASSERT_EQ(a.claim("servo", {0, 1}, 1), "");
  ASSERT_EQ(a.claimed_at("servo"), std::optional<std::uint64_t>(1));
  ASSERT_EQ(a.missing_owners(2), std::vector<std::string>{"servo"});
  ASSERT_EQ(a.claim("servo", {0, 1}, 2), "") << "claimed again while tick 2 waits";
  EXPECT_EQ(a.claimed_at("servo"), std::optional<std::uint64_t>(1)) << "the ticks waited on are unchanged";
  EXPECT_EQ(a.answer_tick("servo", 2), 1u) << "claim_axes answers the first claim's tick";
  EXPECT_EQ(a.answer_tick("other", 2), 2u) << "no claim: the tick the request came at";
  EXPECT_EQ(a.missing_owners(2), std::vector<std::string>{"servo"});
  ASSERT_EQ(a.claim("servo", {0, 1, 2}, 3), "");
  EXPECT_EQ(a.claimed_at("servo"), std::optional<std::uint64_t>(3)) << "a new axis joins at its claim's tick";
  EXPECT_TRUE(a.missing_owners(3).empty());
  ASSERT_EQ(a.release("servo", {}), "");
  EXPECT_FALSE(a.claimed_at("servo").has_value()) << "released: no claim";
}

TEST(AxisArbiter, ARewindMovesLaterClaimsToTheResumedTick) {
  // dem_node resumes a test from a checkpoint of tick 5 after it had
  // published tick 9: a claim of tick 8 held across the load must be
  // waited on from tick 6, and a repeated claim answered tick 5, not 8
  // (the owner would skip ticks 6-8 and dem_node would not wait on it).
  AxisArbiter a = make();
  ASSERT_EQ(a.claim("servo", {0, 1}, 8), "");
  ASSERT_EQ(a.claim("early", {2}, 3), "");
  ASSERT_EQ(a.command("servo", 9, {0, 1}, {1.0, 1.0}, 9, true), "");
  EXPECT_EQ(a.answer_tick("servo", 5), 5u) << "never a tick after the last published one";
  a.rewind(5);
  EXPECT_EQ(a.claimed_at("servo"), std::optional<std::uint64_t>(5));
  EXPECT_EQ(a.claimed_at("early"), std::optional<std::uint64_t>(3)) << "an earlier claim is kept";
  EXPECT_EQ(a.missing_owners(6), (std::vector<std::string>{"early", "servo"}));
  ASSERT_EQ(a.claim("servo", {0, 1}, 5), "");
  EXPECT_EQ(a.answer_tick("servo", 5), 5u);
}

TEST(AxisArbiter, AClaimWithARepeatedAxisIsRefusedNamingTheEntry) {
  AxisArbiter a = make();
  EXPECT_EQ(a.claim("servo", {0, 1, 0}, 0), "axes[2]: axis 0 is repeated");
  EXPECT_EQ(a.owner(0), "") << "a refused claim must not take any axis";
  EXPECT_EQ(a.owner(1), "");
  EXPECT_EQ(a.claim("servo", {0, 1}, 0), "");
}

TEST(AxisArbiter, AClaimWithoutAxesMakesALockstepParticipant) {
  AxisArbiter a = make();
  EXPECT_EQ(a.claim("protocol", {}, 3), "");
  for (int i = 0; i < 3; ++i) EXPECT_EQ(a.owner(i), "") << "a participant owns no axis";
  EXPECT_TRUE(a.missing_owners(3).empty()) << "joined at tick 3: answers from tick 4 on";
  ASSERT_EQ(a.missing_owners(4), std::vector<std::string>{"protocol"});
  EXPECT_EQ(a.command("protocol", 4, {}, {}, 4, true), "") << "an empty command answers the tick";
  EXPECT_TRUE(a.missing_owners(4).empty());
  EXPECT_EQ(a.set_open_loop_rate(2, 1.0), "") << "a participant does not block open-loop axes";
  EXPECT_EQ(a.release("protocol", {}), "");
  EXPECT_TRUE(a.missing_owners(5).empty()) << "released: no longer waited for";
  EXPECT_TRUE(starts_with(a.command("protocol", 5, {}, {}, 5, true), "owner:"));
}

TEST(AxisArbiter, OpenLoopRatesAreCheckedAndOwnedAxesRefused) {
  AxisArbiter a = make();
  EXPECT_EQ(a.set_open_loop_rate(2, 10.0), "");
  EXPECT_EQ(a.rates().z, 10.0);
  EXPECT_TRUE(starts_with(a.set_open_loop_rate(5, 1.0), "axis:"));
  EXPECT_TRUE(starts_with(a.set_open_loop_rate(2, std::nan("")), "strain_rate:"));
  EXPECT_TRUE(starts_with(a.set_open_loop_rate(2, 1001.0), "strain_rate:"));
  EXPECT_EQ(a.set_open_loop_rate(2, -1000.0), "") << "the limit itself is allowed";
  ASSERT_EQ(a.claim("servo", {0}, 0), "");
  const std::string bad = a.set_open_loop_rate(0, 1.0);
  EXPECT_TRUE(starts_with(bad, "axis:")) << bad;
  EXPECT_NE(bad.find("'servo'"), std::string::npos);
  EXPECT_EQ(a.rates().z, -1000.0) << "refusals leave the rates alone";
}

TEST(AxisArbiter, LockstepWaitsForEveryOwnerOfTheTickAndHoldsTheLastCommand) {
  AxisArbiter a = make();
  ASSERT_EQ(a.claim("servo", {0, 1}, 0), "");
  EXPECT_TRUE(a.missing_owners(0).empty()) << "claimed at tick 0: answers from tick 1 on";
  ASSERT_EQ(a.missing_owners(1).size(), 1u);
  EXPECT_EQ(a.rates().x, 0.0) << "no command yet";
  // wrong tick, wrong axis, bad rate, size mismatch: refused, still missing
  EXPECT_TRUE(starts_with(a.command("servo", 0, {0}, {1.0}, 1, true), "tick:"));
  EXPECT_TRUE(starts_with(a.command("servo", 1, {2}, {1.0}, 1, true), "axes:"));
  EXPECT_TRUE(starts_with(a.command("servo", 1, {0}, {1e9}, 1, true), "strain_rate:"));
  EXPECT_TRUE(starts_with(a.command("servo", 1, {0, 1}, {1.0}, 1, true), "strain_rate:"));
  EXPECT_TRUE(starts_with(a.command("nobody", 1, {0}, {1.0}, 1, true), "owner:"));
  EXPECT_EQ(a.missing_owners(1).size(), 1u);
  EXPECT_EQ(a.command("servo", 1, {0, 1}, {1.0, 2.0}, 1, true), "");
  EXPECT_TRUE(a.missing_owners(1).empty());
  EXPECT_EQ(a.rates().x, 1.0);
  EXPECT_EQ(a.rates().y, 2.0);
  // tick 2: no answer -> missing; the rates of tick 1 are held
  EXPECT_EQ(a.missing_owners(2), std::vector<std::string>{"servo"});
  EXPECT_EQ(a.rates().y, 2.0);
  // an owner claiming after tick 2 was published is not waited for at tick 2
  ASSERT_EQ(a.claim("axial", {2}, 2), "");
  EXPECT_EQ(a.missing_owners(2), std::vector<std::string>{"servo"});
  EXPECT_EQ(a.missing_owners(3).size(), 2u);
  a.reset_commands();
  EXPECT_EQ(a.rates().x, 0.0);
  EXPECT_EQ(a.owner(0), "servo");
}

TEST(AxisArbiter, FreeRunningTakesTheNewestCommand) {
  AxisArbiter a = make();
  ASSERT_EQ(a.claim("servo", {0}, 0), "");
  EXPECT_EQ(a.command("servo", 3, {0}, {1.0}, 5, false), "");
  EXPECT_EQ(a.command("servo", 5, {0}, {2.0}, 5, false), "");
  EXPECT_TRUE(starts_with(a.command("servo", 4, {0}, {3.0}, 5, false), "tick:")) << "older than the last";
  EXPECT_TRUE(starts_with(a.command("servo", 6, {0}, {3.0}, 5, false), "tick:")) << "future";
  EXPECT_EQ(a.rates().x, 2.0);
}

TEST(TargetRamp, RampsLinearlyInSimulationTime) {
  TargetRamp r;
  r.reset({100.0, 100.0, 100.0});
  r.ramp(0, 200.0, 1.0, 2.0);
  EXPECT_DOUBLE_EQ(r.value(0.5).x, 100.0);
  EXPECT_DOUBLE_EQ(r.value(2.0).x, 150.0);
  EXPECT_DOUBLE_EQ(r.value(9.0).x, 200.0);
  EXPECT_DOUBLE_EQ(r.value(2.0).y, 100.0);
  r.ramp(0, 0.0, 2.0, 0.0);  // a step from wherever the ramp is
  EXPECT_DOUBLE_EQ(r.value(2.0).x, 0.0);
  EXPECT_DOUBLE_EQ(r.final_targets().x, 0.0);
}
