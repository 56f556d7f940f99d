// rostest lockstep_timeout.test: a closed-loop owner that never answers
// makes the lockstep dem_node hold its last command, count a timeout per
// tick, report it on /diagnostics and go on (never a deadlock); a
// free-running dem_node never waits and takes the newest command.
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>

#include "virtual_triaxial/CellCommand.h"
#include "virtual_triaxial/ClaimAxes.h"
#include "virtual_triaxial/GetInfo.h"
#include "virtual_triaxial/Step.h"

#include "support/rig_test_helpers.h"

namespace vtm = virtual_triaxial;

using vt::rostest::starts_with;
using vt::rostest::wait_until;

namespace {


template <class S>
bool call(const std::string& name, S& srv) {
    return vt::rostest::call_service(name, srv, 60.0);
}

vtm::GetInfo::Response info(const std::string& ns) {
  vtm::GetInfo s;
  EXPECT_TRUE(vt::rostest::call_service_again(ns + "/get_info", s, 60.0));
  return s.response;
}

void claim(const std::string& ns, const std::string& owner, int axis) {
  vtm::ClaimAxes c;
  c.request.owner = owner;
  c.request.axes = {static_cast<std::uint8_t>(axis)};
  ASSERT_TRUE(call(ns + "/claim_axes", c));
  ASSERT_TRUE(c.response.success) << c.response.message;
}

void step(const std::string& ns, std::uint32_t n) {
  vtm::Step s;
  s.request.count = n;
  ASSERT_TRUE(call(ns + "/step", s));
  ASSERT_TRUE(s.response.success) << s.response.message;
}

std::mutex g_mutex;
std::vector<diagnostic_msgs::DiagnosticStatus> g_status;

void on_diagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
  std::lock_guard<std::mutex> lock(g_mutex);
  for (const auto& s : m->status) g_status.push_back(s);
}

bool warned_about_timeouts() {
  std::lock_guard<std::mutex> lock(g_mutex);
  for (const auto& s : g_status)
    if (s.level == diagnostic_msgs::DiagnosticStatus::WARN && s.message.find("lockstep timeout") != std::string::npos)
      return true;
  return false;
}

}  // namespace

TEST(LockstepTimeout, ASilentOwnerCostsOneTimeoutPerTickAndTheRigGoesOn) {
  const vtm::GetInfo::Response before = info("lock");
  ASSERT_TRUE(before.paused);
  claim("lock", "silent", 0);
  const ros::WallTime t = ros::WallTime::now();
  step("lock", 3);
  ASSERT_TRUE(wait_until([] { return info("lock").tick == 3; }, 30.0)) << "the rig stopped (deadlock?)";
  const double wall = (ros::WallTime::now() - t).toSec();
  EXPECT_GE(wall, 0.19) << "did not wait for the owner (ticks 1 and 2 each wait 0.1 s before tick 3)";
  EXPECT_TRUE(wait_until([] { return info("lock").lockstep_timeouts == 3; }, 5.0))
      << info("lock").lockstep_timeouts;
  EXPECT_EQ(info("lock").strain_rate[0], 0.0) << "held command (none yet) must be 0";
  EXPECT_TRUE(wait_until(warned_about_timeouts, 10.0)) << "no WARN on /diagnostics";
  EXPECT_FALSE(info("lock").unstable);
}

TEST(LockstepTimeout, FreeRunningNeverWaitsAndTakesTheNewestCommand) {
  claim("free", "ctl", 0);
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<vtm::CellCommand>("free/cell_command", 10);
  ASSERT_TRUE(wait_until([&] { return pub.getNumSubscribers() > 0; }, 30.0));
  const ros::WallTime t = ros::WallTime::now();
  step("free", 50);
  ASSERT_TRUE(wait_until([] { return info("free").tick == 50; }, 30.0));
  EXPECT_LT((ros::WallTime::now() - t).toSec(), 20.0);
  EXPECT_EQ(info("free").lockstep_timeouts, 0u);

  const double t0 = info("free").t0;
  vtm::CellCommand cmd;
  cmd.tick = 50;
  cmd.owner = "ctl";
  cmd.axes = {0};
  cmd.strain_rate = {-2e-5 / t0};  // extension
  pub.publish(cmd);
  EXPECT_TRUE(wait_until([&] { return info("free").strain_rate[0] == -2e-5 / t0; }, 10.0));
  cmd.tick = 49;  // older than the newest: refused
  cmd.strain_rate = {1e-5 / t0};
  pub.publish(cmd);
  EXPECT_TRUE(wait_until([] { return info("free").rejected_commands == 1; }, 10.0));
  EXPECT_EQ(info("free").strain_rate[0], -2e-5 / t0);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_lockstep_timeout");
  ros::NodeHandle nh;
  ros::Subscriber sub = nh.subscribe("/diagnostics", 1000, on_diagnostics);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return rc;
}
