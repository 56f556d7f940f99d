// rostest claim_answer_lost.test (servo_controller_node) and
// claim_answer_lost_python.test (scripts/py_servo_controller.py): a servo
// keeps lockstep when dem_node ran its claim_axes but the answer was lost.
//
// roscpp can lose the answer of a service call after the server ran it
// (ros/ros_comm#1976). On CI this once left dem_node counting the servo's
// claim from the paused tick while the servo, told "failed", claimed again
// a tick later, skipped the tick dem_node waited on and cost a 5 s lockstep
// timeout and the run's bits. This node plays dem_node with the real
// AxisArbiter and loses claim answers on purpose (the callback runs the
// claim, then fails the call):
//   1. one answer lost during ~enable: the servo claims again at once and
//      enable answers "claimed"; the tick after the claim is answered;
//   2. every answer lost while the rig is paused, then the rig runs on: the
//      state of the tick dem_node waits on arrives before any claim answer
//      does; once answers get through, the servo answers that tick, with the
//      proportional law's command for that state, bit for bit (every tick's
//      state asks for another, unsaturated rate), and nothing is refused.
#include <algorithm>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>

#include "virtual_triaxial/CellCommand.h"
#include "virtual_triaxial/ClaimAxes.h"
#include "virtual_triaxial/GetInfo.h"
#include "virtual_triaxial/ReleaseAxes.h"
#include "virtual_triaxial/Stress.h"
#include "virtual_triaxial/control/proportional_servo.h"
#include "virtual_triaxial/ros/axis_arbiter.h"

#include "support/rig_test_helpers.h"

namespace vtm = virtual_triaxial;
using vt::rostest::call_service;
using vt::rostest::wait_until;

namespace {

constexpr double kT0 = 1e-6;        // [s]
constexpr double kDt = 1e-7;        // control period [s] (publish_every 1)
constexpr double kTarget = 1e5;     // the servo's ~target [Pa]
constexpr double kStiffness = 1e8;  // d sigma / d eps [Pa]
constexpr double kMaxRate = 1e-4 / kT0;  // the servo's cap: ~max_dimensionless_rate / T0 [1/s]
const std::string kOwner = "/servo";

/// Lateral stress of the state of tick `tick` [Pa]: 50 Pa further below the
/// target each tick, so every tick asks for another (unsaturated) rate.
double lateral_stress(std::uint64_t tick) { return kTarget - 50.0 * static_cast<double>(tick); }

/// The proportional law's rates for the lateral axes on the state of `tick`
/// (control/proportional_servo.h, the servo's gain 1 and cap).
std::vector<double> law_rates(std::uint64_t tick) {
  vt::control::ServoParameters p;
  p.gain = 1.0;
  p.max_strain_rate = kMaxRate;
  vt::control::ProportionalServo law(p);
  law.init({kTarget, kTarget, kTarget}, vt::control::AxisMask{true, true, false});
  law.start(0.0);
  vt::control::ServoInput in;
  in.time = static_cast<double>(tick) * kDt;
  in.dt = kDt;
  in.stress = {lateral_stress(tick), lateral_stress(tick), 2 * kTarget};
  in.stiffness = {kStiffness, kStiffness, kStiffness};
  const vt::control::ServoOutput out = law.update(in);
  EXPECT_FALSE(out.saturated[0] || out.saturated[1]) << "tick " << tick << ": the test wants unsaturated rates";
  return {out.strain_rate[0], out.strain_rate[1]};
}

/// dem_node as far as a servo sees it: stress out, cell_command in,
/// get_info, claim_axes (whose answers can be lost), release_axes.
class FakeDem {
 public:
  explicit FakeDem(ros::NodeHandle& nh) {
    arbiter_.set_limit(kT0, 1e-3);
    stress_pub_ = nh.advertise<vtm::Stress>("stress", 10);
    command_sub_ = nh.subscribe("cell_command", 100, &FakeDem::on_command, this);
    services_.push_back(nh.advertiseService("get_info", &FakeDem::on_info, this));
    services_.push_back(nh.advertiseService("claim_axes", &FakeDem::on_claim, this));
    services_.push_back(nh.advertiseService("release_axes", &FakeDem::on_release, this));
  }

  bool connected() const { return stress_pub_.getNumSubscribers() > 0 && command_sub_.getNumPublishers() > 0; }
  /// The next `n` claim answers are lost (n < 0: every one until set again).
  void lose_claim_answers(int n) {
    const std::lock_guard<std::mutex> l(m_);
    lose_ = n;
  }
  int claims() const {
    const std::lock_guard<std::mutex> l(m_);
    return claims_;
  }
  std::optional<std::uint64_t> claimed_at() const {
    const std::lock_guard<std::mutex> l(m_);
    return arbiter_.claimed_at(kOwner);
  }
  std::vector<std::string> missing(std::uint64_t tick) const {
    const std::lock_guard<std::mutex> l(m_);
    return arbiter_.missing_owners(tick);
  }
  /// Strain rates of the accepted command for `tick` (empty if none).
  std::vector<double> command(std::uint64_t tick) const {
    const std::lock_guard<std::mutex> l(m_);
    const auto it = accepted_.find(tick);
    return it == accepted_.end() ? std::vector<double>{} : it->second;
  }
  std::vector<std::string> refusals() const {
    const std::lock_guard<std::mutex> l(m_);
    return refusals_;
  }
  /// Publishes the state of tick `tick` (lateral stresses lateral_stress(tick)).
  void publish(std::uint64_t tick) {
    vtm::Stress s;
    {
      const std::lock_guard<std::mutex> l(m_);
      tick_ = tick;
    }
    s.tick = tick;
    s.time = static_cast<double>(tick) * kDt;
    s.header.stamp.fromSec(s.time);
    s.control_period = kDt;
    s.stress[0] = s.stress[4] = lateral_stress(tick);
    s.stress[8] = 2 * kTarget;
    s.stiffness = {kStiffness, kStiffness, kStiffness};
    stress_pub_.publish(s);
  }

 private:
  bool on_info(vtm::GetInfo::Request&, vtm::GetInfo::Response& rs) {
    const std::lock_guard<std::mutex> l(m_);
    rs.t0 = kT0;
    rs.dt = kDt;
    rs.time = static_cast<double>(tick_) * kDt;
    rs.tick = rs.answered_tick = tick_;
    rs.publish_every = 1;
    rs.lockstep = true;
    rs.paused = true;
    rs.max_dimensionless_rate = arbiter_.max_dimensionless_rate();
    for (int a = 0; a < 3; ++a) rs.axis_owners[static_cast<std::size_t>(a)] = arbiter_.owner(a);
    return true;
  }
  bool on_claim(vtm::ClaimAxes::Request& rq, vtm::ClaimAxes::Response& rs) {
    const std::lock_guard<std::mutex> l(m_);
    ++claims_;
    std::vector<int> axes(rq.axes.begin(), rq.axes.end());
    rs.message = arbiter_.claim(rq.owner, axes, tick_);
    rs.success = rs.message.empty();
    rs.tick = rs.success ? arbiter_.answer_tick(rq.owner, tick_) : tick_;  // as dem_node answers
    if (lose_ == 0) return true;
    if (lose_ > 0) --lose_;
    return false;  // the claim took effect; the caller's call fails
  }
  bool on_release(vtm::ReleaseAxes::Request& rq, vtm::ReleaseAxes::Response& rs) {
    const std::lock_guard<std::mutex> l(m_);
    rs.message = arbiter_.release(rq.owner, std::vector<int>(rq.axes.begin(), rq.axes.end()));
    rs.success = rs.message.empty();
    return true;
  }
  void on_command(const vtm::CellCommand::ConstPtr& c) {
    const std::lock_guard<std::mutex> l(m_);
    const std::string bad = arbiter_.command(c->owner, c->tick, std::vector<int>(c->axes.begin(), c->axes.end()),
                                             c->strain_rate, tick_, true);
    if (bad.empty())
      accepted_[c->tick] = c->strain_rate;
    else
      refusals_.push_back("tick " + std::to_string(c->tick) + ": " + bad);
  }

  mutable std::mutex m_;
  vt::ros::AxisArbiter arbiter_;
  std::uint64_t tick_ = 0;
  int lose_ = 0, claims_ = 0;
  std::map<std::uint64_t, std::vector<double>> accepted_;
  std::vector<std::string> refusals_;
  ros::Publisher stress_pub_;
  ros::Subscriber command_sub_;
  std::vector<ros::ServiceServer> services_;
};

FakeDem* g_dem = nullptr;

std_srvs::Trigger::Response trigger(const std::string& name) {
  std_srvs::Trigger t;
  EXPECT_TRUE(call_service(name, t, 60.0)) << name;
  return t.response;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST(ClaimAnswerLost, OneLostAnswerIsClaimedAgainBeforeEnableAnswers) {
  FakeDem& dem = *g_dem;
  ASSERT_TRUE(wait_until([&] { return dem.connected(); }, 60.0)) << "the servo did not connect";
  dem.publish(1);  // the paused rig's last state
  // The servo sees both connections too once an enable claims (answers intact).
  ASSERT_TRUE(wait_until([&] { return !contains(trigger(kOwner + "/enable").message, "not claimed"); }, 60.0));
  ASSERT_TRUE(trigger(kOwner + "/disable").success);
  ASSERT_FALSE(dem.claimed_at().has_value());
  const int before = dem.claims();
  dem.lose_claim_answers(1);
  const std_srvs::Trigger::Response r = trigger(kOwner + "/enable");
  EXPECT_TRUE(r.success) << r.message;
  EXPECT_FALSE(contains(r.message, "not claimed")) << r.message;
  EXPECT_EQ(dem.claims() - before, 2) << "the claim whose answer was lost is made once more";
  EXPECT_EQ(dem.claimed_at(), std::optional<std::uint64_t>(1));

  dem.publish(2);  // resumed: dem_node waits on the servo for tick 2
  EXPECT_TRUE(wait_until([&] { return dem.missing(2).empty(); }, 5.0)) << "tick 2 not answered";
  EXPECT_EQ(dem.command(2), law_rates(2));
  EXPECT_TRUE(dem.refusals().empty()) << dem.refusals().front();
}

TEST(ClaimAnswerLost, AnswersLostUntilTheRigRunsAreRecoveredOnTheTickItWaitsOn) {
  FakeDem& dem = *g_dem;
  ASSERT_EQ(dem.command(2).size(), 2u) << "test 1 did not run";
  ASSERT_TRUE(trigger(kOwner + "/disable").success);
  ASSERT_FALSE(dem.claimed_at().has_value()) << "disable released the axes";

  dem.lose_claim_answers(-1);
  const int before = dem.claims();
  const std_srvs::Trigger::Response r = trigger(kOwner + "/enable");
  EXPECT_TRUE(r.success) << r.message;
  EXPECT_TRUE(contains(r.message, "not claimed")) << r.message;
  ASSERT_GT(dem.claims(), before);
  ASSERT_EQ(dem.claimed_at(), std::optional<std::uint64_t>(2)) << "the lost claim took effect at tick 2";

  // The rig runs on: tick 3, which dem_node waits on the servo for, reaches
  // the servo before any claim answer does.
  dem.publish(3);
  ros::WallDuration(0.5).sleep();  // the servo's own retries (every 0.2 s) still lose their answers
  ASSERT_EQ(dem.missing(3), std::vector<std::string>{kOwner}) << "answered without a claim answer";
  const int lost = dem.claims() - before;
  dem.lose_claim_answers(0);
  EXPECT_TRUE(wait_until([&] { return dem.missing(3).empty(); }, 5.0))
      << "tick 3 not answered after the claim answers got through";
  EXPECT_EQ(dem.claimed_at(), std::optional<std::uint64_t>(2)) << "claims made again keep the first tick";
  EXPECT_EQ(dem.command(3), law_rates(3)) << "the law's command for the state of tick 3";
  EXPECT_NE(law_rates(3), law_rates(2)) << "states that differ ask for different rates";
  dem.publish(4);
  EXPECT_TRUE(wait_until([&] { return dem.missing(4).empty(); }, 5.0)) << "tick 4 not answered";
  EXPECT_TRUE(dem.refusals().empty()) << dem.refusals().front();
  std::printf("[claim_answer_lost] %d claim answers lost while paused and after tick 3; tick 3 answered\n", lost);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "claim_answer_lost");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  FakeDem dem(nh);
  g_dem = &dem;
  const int rc = RUN_ALL_TESTS();
  g_dem = nullptr;
  return rc;
}
