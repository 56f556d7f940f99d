// rostest live_tuning.test: live tuning of the rig with dynamic_reconfigure
// (cfg/Servo.cfg on /servo/set_parameters, cfg/Dem.cfg on
// /dem_node/set_parameters), on a rig that starts paused and is stepped one
// control tick at a time (lockstep), so every check is tick-exact:
//   1. the reconfigure servers start from the nodes' parameters (not from
//      the .cfg defaults) and the parameter server keeps them;
//   2. a gain change shows in the next servo_state, and the next command is
//      the law's rate with the new gain: rate = -g e / (K dt) on each servo
//      axis (K from the tick's Stress, dt = control_period; ki = kd = 0), then
//      -(g + ki) e / (K dt) on the first tick after ki is switched on (the
//      integral term starts empty); a rate-limit change is reported / T0;
//   3. dem_node's damping_ratio / damping_model changes show in get_info;
//   4. invalid values are refused (the old value kept, a ROS_WARN on /rosout
//      naming the field) and both nodes keep running;
//   5. every change is on the latched ~parameter_updates topics.
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <dynamic_reconfigure/Config.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>

#include "virtual_triaxial/CellCommand.h"
#include "virtual_triaxial/GetInfo.h"
#include "virtual_triaxial/ServoState.h"
#include "virtual_triaxial/Step.h"
#include "virtual_triaxial/Stress.h"

#include "support/rig_test_helpers.h"

namespace vtm = virtual_triaxial;
using dynamic_reconfigure::Config;

using vt::rostest::starts_with;
using vt::rostest::wait_until;

namespace {

constexpr double kTarget = 100e3;  // servo target [Pa]


/// Value of a double / string parameter in a dynamic_reconfigure Config (NaN / "" if absent).
double dbl(const Config& c, const std::string& name) {
  for (const auto& d : c.doubles)
    if (d.name == name) return d.value;
  return std::nan("");
}
std::string str(const Config& c, const std::string& name) {
  for (const auto& s : c.strs)
    if (s.name == name) return s.value;
  return "";
}

class Rig {
 public:
  Rig() {
    stress_sub_ = nh_.subscribe("stress", 1000, &Rig::on_stress, this);
    state_sub_ = nh_.subscribe("servo_state", 1000, &Rig::on_state, this);
    command_sub_ = nh_.subscribe("cell_command", 1000, &Rig::on_command, this);
    rosout_sub_ = nh_.subscribe("/rosout", 1000, &Rig::on_log, this);
    servo_updates_ = nh_.subscribe("/servo/parameter_updates", 10, &Rig::on_servo_update, this);
    dem_updates_ = nh_.subscribe("/dem_node/parameter_updates", 10, &Rig::on_dem_update, this);
  }

  template <class S>
  bool call(const std::string& name, S& srv) {
    return vt::rostest::call_service(name, srv, 60.0);
  }

  vtm::GetInfo::Response info() {
    vtm::GetInfo s;
    EXPECT_TRUE(vt::rostest::call_service_again("get_info", s, 60.0));
    return s.response;
  }

  /// set_parameters on `node` ("/servo", "/dem_node") with one double or
  /// string field (none: just read the config); returns the reply's config.
  Config reconfigure(const std::string& node, const std::string& name = "", double value = 0.0) {
    dynamic_reconfigure::Reconfigure r;
    if (!name.empty()) {
      dynamic_reconfigure::DoubleParameter d;
      d.name = name;
      d.value = value;
      r.request.config.doubles.push_back(d);
    }
    EXPECT_TRUE(call(node + "/set_parameters", r)) << node;
    return r.response.config;
  }
  Config reconfigure_str(const std::string& node, const std::string& name, const std::string& value) {
    dynamic_reconfigure::Reconfigure r;
    dynamic_reconfigure::StrParameter s;
    s.name = name;
    s.value = value;
    r.request.config.strs.push_back(s);
    EXPECT_TRUE(call(node + "/set_parameters", r)) << node;
    return r.response.config;
  }

  /// Steps one control tick; returns its number once its Stress, ServoState
  /// and CellCommand have arrived (0 on failure).
  std::uint64_t step() {
    // A state published before our subscriptions connect is lost to us (on
    // a loaded machine the first step can come before that): wait for them.
    EXPECT_TRUE(wait_until(
        [&] {
          // /rosout: this node (intraprocess), dem_node and the servo; a
          // log line sent before its connection is lost to us as well
          return stress_sub_.getNumPublishers() > 0 && state_sub_.getNumPublishers() > 0 &&
                 command_sub_.getNumPublishers() > 0 && rosout_sub_.getNumPublishers() >= 3;
        },
        30.0))
        << "stress / servo_state / cell_command / rosout not connected (rosout publishers: "
        << rosout_sub_.getNumPublishers() << ")";
    const std::uint64_t k = info().tick + 1;
    vtm::Step st;
    st.request.count = 1;
    EXPECT_TRUE(call("step", st));
    EXPECT_TRUE(st.response.success) << st.response.message;
    const bool ok = wait_until(
        [&] {
          std::lock_guard<std::mutex> lock(mutex_);
          return stress_.count(k) && state_.count(k) && command_.count(k);
        },
        30.0);
    EXPECT_TRUE(ok) << "tick " << k << " not answered";
    return ok ? k : 0;
  }

  vtm::Stress stress(std::uint64_t k) {
    std::lock_guard<std::mutex> lock(mutex_);
    return stress_[k];
  }
  vtm::ServoState state(std::uint64_t k) {
    std::lock_guard<std::mutex> lock(mutex_);
    return state_[k];
  }
  vtm::CellCommand command(std::uint64_t k) {
    std::lock_guard<std::mutex> lock(mutex_);
    return command_[k];
  }
  bool logged(std::uint8_t level, const std::string& node, const std::string& a, const std::string& b) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& m : logs_)
      if (m.level == level && m.name == node && m.msg.find(a) != std::string::npos &&
          m.msg.find(b) != std::string::npos)
        return true;
    return false;
  }
  Config last_update(const std::string& node) {
    std::lock_guard<std::mutex> lock(mutex_);
    return node == "/servo" ? servo_update_ : dem_update_;
  }

 private:
  void on_stress(const vtm::Stress::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex_);
    stress_[m->tick] = *m;
  }
  void on_state(const vtm::ServoState::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex_);
    state_[m->tick] = *m;
  }
  void on_command(const vtm::CellCommand::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex_);
    command_[m->tick] = *m;
  }
  void on_log(const rosgraph_msgs::Log::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex_);
    logs_.push_back(*m);
  }
  void on_servo_update(const Config::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex_);
    servo_update_ = *m;
  }
  void on_dem_update(const Config::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex_);
    dem_update_ = *m;
  }

  ros::NodeHandle nh_;
  ros::Subscriber stress_sub_, state_sub_, command_sub_, rosout_sub_, servo_updates_, dem_updates_;
  std::mutex mutex_;
  std::map<std::uint64_t, vtm::Stress> stress_;
  std::map<std::uint64_t, vtm::ServoState> state_;
  std::map<std::uint64_t, vtm::CellCommand> command_;
  std::vector<rosgraph_msgs::Log> logs_;
  Config servo_update_, dem_update_;
};

Rig* g_rig = nullptr;

/// The servo's command of tick k is the stiffness-normalised law with action
/// factor `factor` (g, or g + ki on the first integrating tick): on x and y
/// rate = -factor e / (K dt), unsaturated; the CellCommand carries it.
void expect_law(Rig& rig, std::uint64_t k, double factor) {
  const vtm::Stress s = rig.stress(k);
  const vtm::ServoState st = rig.state(k);
  const vtm::CellCommand cmd = rig.command(k);
  ASSERT_EQ(cmd.axes.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    const auto a = static_cast<std::size_t>(i);
    EXPECT_NEAR(st.errors[a], s.stress[4 * a] - kTarget, 1e-9 * kTarget);
    ASSERT_GT(s.stiffness[a], 0.0);
    ASSERT_NE(st.errors[a], 0.0) << "a zero error would make the check vacuous";
    ASSERT_FALSE(st.saturated[a]) << "axis " << i << ": the check needs the unsaturated law";
    const double expected = -factor * st.errors[a] / (s.stiffness[a] * s.control_period);
    EXPECT_NEAR(st.strain_rate[a], expected, 1e-12 * std::abs(expected) + 1e-300) << "tick " << k << " axis " << i;
    EXPECT_EQ(cmd.axes[a], i);
    EXPECT_EQ(cmd.strain_rate[a], st.strain_rate[a]);
  }
}

}  // namespace

TEST(LiveTuning, ServersStartFromTheNodesParameters) {
  Rig& rig = *g_rig;
  ASSERT_TRUE(wait_until(
      [&] {
        const vtm::GetInfo::Response i = rig.info();
        return i.axis_owners[0] == "/servo" && i.axis_owners[1] == "/servo";
      },
      60.0))
      << "the servo did not claim x and y";
  const Config s = rig.reconfigure("/servo");  // empty request: read the config
  EXPECT_DOUBLE_EQ(dbl(s, "gain"), 0.7);
  EXPECT_DOUBLE_EQ(dbl(s, "max_dimensionless_rate"), 2e-4);
  EXPECT_DOUBLE_EQ(dbl(s, "ki"), 0.0);
  EXPECT_DOUBLE_EQ(dbl(s, "kd"), 0.0);
  EXPECT_DOUBLE_EQ(dbl(s, "max_rate_change"), 0.0);
  double g = 0.0;
  EXPECT_TRUE(ros::param::get("/servo/gain", g));
  EXPECT_DOUBLE_EQ(g, 0.7) << "the server overwrote ~gain with the .cfg default";

  const vtm::GetInfo::Response i = rig.info();
  const Config d = rig.reconfigure("/dem_node");
  EXPECT_DOUBLE_EQ(i.damping_ratio, 0.07);
  EXPECT_DOUBLE_EQ(dbl(d, "damping_ratio"), 0.07);
  EXPECT_EQ(str(d, "damping_model"), i.damping_model);
}

TEST(LiveTuning, ServoChangesTakeEffectOnTheNextControlUpdate) {
  Rig& rig = *g_rig;
  std::uint64_t k = rig.step();
  ASSERT_GT(k, 0u);
  EXPECT_DOUBLE_EQ(rig.state(k).gain, 0.7);
  EXPECT_EQ(rig.state(k).strategy, "pid");
  expect_law(rig, k, 0.7);

  Config c = rig.reconfigure("/servo", "gain", 0.35);
  EXPECT_DOUBLE_EQ(dbl(c, "gain"), 0.35);
  k = rig.step();
  ASSERT_GT(k, 0u);
  EXPECT_DOUBLE_EQ(rig.state(k).gain, 0.35);
  expect_law(rig, k, 0.35);

  c = rig.reconfigure("/servo", "ki", 0.2);
  EXPECT_DOUBLE_EQ(dbl(c, "ki"), 0.2);
  EXPECT_DOUBLE_EQ(dbl(c, "gain"), 0.35);
  k = rig.step();
  ASSERT_GT(k, 0u);
  EXPECT_DOUBLE_EQ(rig.state(k).ki, 0.2);
  expect_law(rig, k, 0.35 + 0.2);  // S = ki e on the first integrating tick

  c = rig.reconfigure("/servo", "max_rate_change", 5e-5);
  EXPECT_DOUBLE_EQ(dbl(c, "max_rate_change"), 5e-5);
  k = rig.step();
  ASSERT_GT(k, 0u);
  const double t0 = rig.info().t0;
  EXPECT_NEAR(rig.state(k).max_rate_change, 5e-5 / t0, 1e-12 * 5e-5 / t0);
  EXPECT_NEAR(rig.state(k).max_strain_rate, 2e-4 / t0, 1e-12 * 2e-4 / t0);
  for (int i = 0; i < 2; ++i)
    EXPECT_LE(std::abs(rig.state(k).strain_rate[i] - rig.state(k - 1).strain_rate[i]), 5e-5 / t0 * (1 + 1e-9));
  EXPECT_TRUE(wait_until([&] { return rig.logged(rosgraph_msgs::Log::INFO, "/servo", "live tuning", "ki 0 -> 0.2"); },
                         10.0))
      << "no ROS_INFO for the ki change";
}

TEST(LiveTuning, DemDampingChangesShowInGetInfo) {
  Rig& rig = *g_rig;
  Config c = rig.reconfigure("/dem_node", "damping_ratio", 0.3);
  EXPECT_DOUBLE_EQ(dbl(c, "damping_ratio"), 0.3);
  EXPECT_DOUBLE_EQ(rig.info().damping_ratio, 0.3);
  c = rig.reconfigure_str("/dem_node", "damping_model", "ND");
  EXPECT_EQ(str(c, "damping_model"), "ND");
  EXPECT_DOUBLE_EQ(dbl(c, "damping_ratio"), 0.3);
  const vtm::GetInfo::Response i = rig.info();
  EXPECT_EQ(i.damping_model, "ND");
  EXPECT_DOUBLE_EQ(i.damping_ratio, 0.3);
  EXPECT_GT(rig.step(), 0u) << "dem_node stopped stepping after a damping change";
}

TEST(LiveTuning, InvalidValuesAreRefusedAndTheNodesKeepRunning) {
  Rig& rig = *g_rig;
  struct Bad { const char* name; double value; double kept; };
  for (const Bad& b : {Bad{"gain", 1.5, 0.35}, Bad{"gain", 0.0, 0.35}, Bad{"gain", std::nan(""), 0.35},
                       Bad{"ki", -0.1, 0.2}, Bad{"kd", 0.5, 0.0}, Bad{"max_rate_change", -1.0, 5e-5},
                       Bad{"max_dimensionless_rate", 0.01, 2e-4}}) {  // 0.01: above dem_node's 1e-3
    SCOPED_TRACE(std::string(b.name) + " = " + std::to_string(b.value));
    const Config c = rig.reconfigure("/servo", b.name, b.value);
    EXPECT_DOUBLE_EQ(dbl(c, b.name), b.kept);
  }
  EXPECT_TRUE(wait_until([&] { return rig.logged(rosgraph_msgs::Log::WARN, "/servo", "~gain", "refused"); }, 10.0))
      << "no ROS_WARN naming ~gain";
  EXPECT_TRUE(wait_until(
      [&] { return rig.logged(rosgraph_msgs::Log::WARN, "/servo", "~max_dimensionless_rate", "dem_node's limit"); },
      10.0));
  Config d = rig.reconfigure("/dem_node", "damping_ratio", -1.0);
  EXPECT_DOUBLE_EQ(dbl(d, "damping_ratio"), 0.3);
  d = rig.reconfigure_str("/dem_node", "damping_model", "XY");
  EXPECT_EQ(str(d, "damping_model"), "ND");
  EXPECT_TRUE(wait_until(
      [&] { return rig.logged(rosgraph_msgs::Log::WARN, "/dem_node", "~damping_ratio", "refused"); }, 10.0));

  // both nodes still run, with the old values
  const std::uint64_t k = rig.step();
  ASSERT_GT(k, 0u);
  EXPECT_DOUBLE_EQ(rig.state(k).gain, 0.35);
  EXPECT_DOUBLE_EQ(rig.state(k).ki, 0.2);
  EXPECT_DOUBLE_EQ(rig.state(k).kd, 0.0);
  const vtm::GetInfo::Response i = rig.info();
  EXPECT_DOUBLE_EQ(i.damping_ratio, 0.3);
  EXPECT_EQ(i.damping_model, "ND");
  EXPECT_EQ(i.lockstep_timeouts, 0u);
  EXPECT_EQ(i.rejected_commands, 0u);
  double g = 0.0;
  EXPECT_TRUE(ros::param::get("/servo/gain", g));
  EXPECT_DOUBLE_EQ(g, 0.35);
}

TEST(LiveTuning, ChangesAreOnTheParameterUpdatesTopics) {
  Rig& rig = *g_rig;
  EXPECT_TRUE(wait_until([&] { return dbl(rig.last_update("/servo"), "gain") == 0.35; }, 10.0));
  EXPECT_DOUBLE_EQ(dbl(rig.last_update("/servo"), "ki"), 0.2);
  EXPECT_TRUE(wait_until([&] { return dbl(rig.last_update("/dem_node"), "damping_ratio") == 0.3; }, 10.0));
  EXPECT_EQ(str(rig.last_update("/dem_node"), "damping_model"), "ND");
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_live_tuning");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  Rig rig;
  g_rig = &rig;
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return rc;
}
