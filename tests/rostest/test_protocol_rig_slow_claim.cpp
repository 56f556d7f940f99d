// rostest protocol_rig_slow_claim.test: the protocol rig with a servo that
// claims its axes only ~claim_delay wall seconds after each ~enable
// (tests/rostest/support/slow_claim_servo.py) and a protocol node with
// ~rig_timeout 4 s:
//   1. claims 1 s late: test_protocol_node starts each stage only once
//      dem_node lists the stage's closed-loop owners, so the drained mini
//      test completes without a lockstep timeout, sane and with rising
//      stamps, and gives the headless triax_run's summary (9 digits); the
//      wait did happen (> 2 s wall);
//   2. a servo that never claims: the test fails within the rig timeout
//      (+ margin) with a message naming the stage and the open axes, and
//      the rig never ran a tick of it.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <yaml-cpp/yaml.h>

#include "support/protocol_rig_client.h"

namespace {
constexpr double kClaimDelay = 1.0;  // s, = servo/claim_delay of the .test
constexpr double kRigTimeout = 4.0;  // s, = test_protocol_node/rig_timeout of the .test
}  // namespace

TEST(ProtocolRigSlowClaim, StagesWaitForTheClaimAndMatchTriaxRun) {
  Rig& rig = *g_rig;
  ASSERT_TRUE(rig.ready()) << "no run_test action server / rig topics";
  const TestRun r = rig.run(file_goal("drained_mini.yaml", "drained_slow_claim"));
  ASSERT_TRUE(r.finished) << "no result within " << kRunTimeout << " s";
  std::printf("[protocol_rig_slow_claim] drained mini: %s in %.1f s wall, %llu ticks\n", r.result.verdict.c_str(),
              r.wall, static_cast<unsigned long long>(r.result.ticks));
  ASSERT_EQ(r.result.verdict, "completed") << r.result.message;
  expect_sane_summary(r);
  expect_stamps_rising(r);
  EXPECT_GT(r.wall, 2 * kClaimDelay) << "the claims were not held back: the test proves nothing";
  EXPECT_EQ(rig.info().lockstep_timeouts, 0u);
  expect_same_as_triax_run(r, "drained_mini.yaml", "headless_slow_claim");
}

TEST(ProtocolRigSlowClaim, AServoThatNeverClaimsFailsTheTestNamingTheAxes) {
  Rig& rig = *g_rig;
  const std::uint64_t tick0 = rig.info().tick;
  ros::param::set("/servo/claim_delay", 1e6);
  const TestRun r = rig.run(file_goal("drained_mini.yaml", "drained_no_claim"), 60.0);
  ros::param::set("/servo/claim_delay", kClaimDelay);
  ASSERT_TRUE(r.finished);
  std::printf("[protocol_rig_slow_claim] never claimed: %s in %.1f s wall: %s\n", r.result.verdict.c_str(), r.wall,
              r.result.message.c_str());
  EXPECT_EQ(r.result.verdict, "failed");
  EXPECT_TRUE(contains(r.result.message, "stage 'consolidation'")) << r.result.message;
  EXPECT_TRUE(contains(r.result.message, "cell axes 0, 1, 2 have no closed-loop owner")) << r.result.message;
  EXPECT_GE(r.wall, kRigTimeout);
  EXPECT_LT(r.wall, kRigTimeout + 20.0) << "the wait is bounded by ~rig_timeout";
  EXPECT_EQ(rig.info().tick, tick0) << "the stage ran without its servo";
}

int main(int argc, char** argv) { return run_rig_tests(argc, argv, "test_protocol_rig_slow_claim"); }
