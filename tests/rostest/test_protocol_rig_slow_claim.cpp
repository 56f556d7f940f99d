// rostest protocol_rig_slow_claim.test: the protocol rig with a servo that
// claims badly (tests/rostest/support/slow_claim_servo.py, the Python servo
// with ~claim_delay and ~lost_claim_answers read at each ~enable) and a
// protocol node with ~rig_timeout 8 s:
//   1. claims 1 s late: test_protocol_node starts each stage only once the
//      servo holds its axes (dem_node lists it as the owner of every axis
//      when the first stage's `running` status comes), so the drained mini
//      test completes without a lockstep
//      timeout, sane and with rising stamps, and gives the headless
//      triax_run's summary (9 digits);
//   2. the answers of the first 4 claim calls of each stage lost after
//      dem_node ran them (the CI failure of 2026-12-05, on the real rig):
//      the same summary as triax_run, no lockstep timeout;
//   3. a servo that never claims: the test fails within the rig timeout
//      (+ margin) with a message naming the stage and the open axes, and
//      the rig never ran a tick of it.
#include <cstdio>
#include <mutex>
#include <optional>
#include <string>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <yaml-cpp/yaml.h>

#include "support/protocol_rig_client.h"

namespace {

constexpr double kClaimDelay = 1.0;  // s, test 1's servo/claim_delay
constexpr double kRigTimeout = 8.0;  // s, = test_protocol_node/rig_timeout of the .test

/// The first `running` protocol_status after arm(): its wall time and the
/// axis owners dem_node lists right then (get_info from the callback; the
/// status goes out while dem_node is still paused at the stage's start).
class FirstStageStart {
 public:
  FirstStageStart() { sub_ = nh_.subscribe("protocol_status", 100, &FirstStageStart::on_status, this); }
  bool connected() const { return sub_.getNumPublishers() > 0; }
  void arm() {
    const std::lock_guard<std::mutex> l(m_);
    at_.reset();
  }
  std::optional<ros::WallTime> at() const {
    const std::lock_guard<std::mutex> l(m_);
    return at_;
  }
  boost::array<std::string, 3> owners() const {
    const std::lock_guard<std::mutex> l(m_);
    return owners_;
  }

 private:
  void on_status(const vtm::ProtocolStatus::ConstPtr& s) {
    {
      const std::lock_guard<std::mutex> l(m_);
      if (at_ || s->state != "running") return;
      at_ = ros::WallTime::now();
    }
    vtm::GetInfo info;
    const bool ok = vt::rostest::call_service_again("get_info", info, 0.0);  // a lost answer: asked again
    const std::lock_guard<std::mutex> l(m_);
    if (ok) owners_ = info.response.axis_owners;
  }
  ros::NodeHandle nh_;
  ros::Subscriber sub_;
  mutable std::mutex m_;
  std::optional<ros::WallTime> at_;
  boost::array<std::string, 3> owners_;
};

void servo_claims(double delay, int lost_answers) {
  ros::param::set("/servo/claim_delay", delay);
  ros::param::set("/servo/lost_claim_answers", lost_answers);
}

}  // namespace

TEST(ProtocolRigSlowClaim, StagesWaitForALateClaimAndMatchTriaxRun) {
  Rig& rig = *g_rig;
  ASSERT_TRUE(rig.ready()) << "no run_test action server / rig topics";
  FirstStageStart start;
  ASSERT_TRUE(wait_until([&] { return start.connected(); }, 30.0)) << "no protocol_status publisher";
  servo_claims(kClaimDelay, 0);
  start.arm();
  const ros::WallTime sent = ros::WallTime::now();
  const TestRun r = rig.run(file_goal("drained_mini.yaml", "drained_slow_claim"));
  ASSERT_TRUE(r.finished) << "no result within " << kRunTimeout << " s";
  std::printf("[protocol_rig_slow_claim] claims 1 s late: %s in %.1f s wall, %llu ticks\n",
              r.result.verdict.c_str(), r.wall, static_cast<unsigned long long>(r.result.ticks));
  ASSERT_EQ(r.result.verdict, "completed") << r.result.message;
  ASSERT_TRUE(start.at().has_value()) << "no running status";
  std::printf("[protocol_rig_slow_claim] first stage started %.2f s after the goal\n", (*start.at() - sent).toSec());
  for (int a = 0; a < 3; ++a)
    EXPECT_EQ(start.owners()[static_cast<std::size_t>(a)], "/servo")
        << "axis " << a << ": the consolidation stage started before the servo's claim";
  expect_sane_summary(r);
  expect_stamps_rising(r);
  EXPECT_EQ(rig.info().lockstep_timeouts, 0u);
  expect_same_as_triax_run(r, "drained_mini.yaml", "headless_slow_claim");
}

TEST(ProtocolRigSlowClaim, LostClaimAnswersOnTheRigStillMatchTriaxRun) {
  Rig& rig = *g_rig;
  servo_claims(0.0, 4);
  const TestRun r = rig.run(file_goal("drained_mini.yaml", "drained_lost_answers"));
  servo_claims(kClaimDelay, 0);
  ASSERT_TRUE(r.finished) << "no result within " << kRunTimeout << " s";
  std::printf("[protocol_rig_slow_claim] 4 claim answers lost per stage: %s in %.1f s wall\n",
              r.result.verdict.c_str(), r.wall);
  ASSERT_EQ(r.result.verdict, "completed") << r.result.message;
  EXPECT_EQ(rig.info().lockstep_timeouts, 0u);
  expect_same_as_triax_run(r, "drained_mini.yaml", "headless_lost_answers");
}

TEST(ProtocolRigSlowClaim, AServoThatNeverClaimsFailsTheTestNamingTheAxes) {
  Rig& rig = *g_rig;
  const std::uint64_t tick0 = rig.info().tick;
  servo_claims(1e6, 0);
  const TestRun r = rig.run(file_goal("drained_mini.yaml", "drained_no_claim"), 60.0);
  servo_claims(kClaimDelay, 0);
  ASSERT_TRUE(r.finished);
  std::printf("[protocol_rig_slow_claim] never claimed: %s in %.1f s wall: %s\n", r.result.verdict.c_str(), r.wall,
              r.result.message.c_str());
  EXPECT_EQ(r.result.verdict, "failed");
  EXPECT_TRUE(contains(r.result.message, "stage 'consolidation'")) << r.result.message;
  EXPECT_TRUE(contains(r.result.message, "cell axes 0, 1, 2 have no closed-loop owner")) << r.result.message;
  EXPECT_GE(r.wall, kRigTimeout);
  EXPECT_LT(r.wall, kRigTimeout + 10.0) << "the wait is bounded by ~rig_timeout";
  const vtm::GetInfo::Response i = rig.info();
  EXPECT_EQ(i.tick, tick0) << "the stage ran without its servo";
  EXPECT_TRUE(i.paused);
  for (int a = 0; a < 3; ++a) EXPECT_EQ(i.axis_owners[static_cast<std::size_t>(a)], "") << "axis " << a;
}

int main(int argc, char** argv) { return run_rig_tests(argc, argv, "test_protocol_rig_slow_claim"); }
