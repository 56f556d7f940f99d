// rostest drained_mini.test: node wiring of the rig (dem_node + servo
// controller) on a 200-sphere sample prepared at 100 kPa.
//
// The sample tests/data/sample_200_100kPa.h5 was made with
//   build/devel/lib/virtual_triaxial/triax_prepare
//     --psd config/samples/psd_uniform4_0.8-1.2mm.yaml --pressure 100000
//     --mu1 0.3 --seed 1 --particles 200 --out tests/data/sample_200_100kPa.h5
// (250 s here, too slow to redo at test time; 86 KB).
//
// The tests run in order (gtest keeps the order of definition) against one
// rig that starts paused:
//   1. the rig comes up: the servo owns x and y, z is open loop;
//   2. bad requests are refused with the field named, the node keeps going
//      and the next good request works;
//   3. a second claim on an owned axis is refused; releasing frees it;
//   4. run A: drained shear at eps' = 1e-5 for 1500 control ticks (3000 DEM
//      steps): lateral stresses within 1 % RMS of 100 kPa (ASTM D4767),
//      axial log strain = rate * time to 1e-6 relative, ticks consecutive,
//      stamps strictly rising in simulation time, no lockstep timeout;
//   5. run B: load the start state saved before run A and repeat: the stress
//      and strain series are bit-identical (lockstep determinism).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <std_srvs/Trigger.h>

#include "virtual_triaxial/ClaimAxes.h"
#include "virtual_triaxial/GetInfo.h"
#include "virtual_triaxial/LoadSample.h"
#include "virtual_triaxial/ReleaseAxes.h"
#include "virtual_triaxial/SaveSample.h"
#include "virtual_triaxial/SetConfiningPressure.h"
#include "virtual_triaxial/SetDamping.h"
#include "virtual_triaxial/SetFriction.h"
#include "virtual_triaxial/SetStrainRate.h"
#include "virtual_triaxial/Step.h"
#include "virtual_triaxial/Strain.h"
#include "virtual_triaxial/Stress.h"

#include "support/rig_test_helpers.h"
#include "support/stress_strain_log.h"

namespace vtm = virtual_triaxial;

using vt::rostest::starts_with;
using vt::rostest::wait_until;

namespace {

constexpr double kTarget = 100e3;        // confining pressure [Pa]
constexpr double kEpsPrime = 1e-5;       // axial eps' = rate * T0
constexpr std::uint32_t kTicks = 1500;   // control ticks per run (x publish_every 2 = 3000 steps)
const char* const kServo = "/servo";     // the servo's owner name (its node name)



struct Series {
  std::vector<vtm::Stress> stress;
  std::vector<vtm::Strain> strain;
  double t_start = 0, rate = 0;
  std::uint64_t k0 = 0;
};

/// Subscriptions and service calls of the test node.
class Rig {
 public:
  Rig() : log_(nh_) {
    clock_sub_ = nh_.subscribe("/clock", 100000, &Rig::on_clock, this);
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

  vtm::SetStrainRate::Response set_rate(int axis, double rate, bool dimensionless) {
    vtm::SetStrainRate s;
    s.request.axis = static_cast<std::uint8_t>(axis);
    s.request.strain_rate = rate;
    s.request.dimensionless = dimensionless;
    EXPECT_TRUE(call("set_strain_rate", s));
    return s.response;
  }

  template <class S>
  typename S::Response claim_like(const std::string& name, const std::string& owner, std::vector<std::uint8_t> axes) {
    S s;
    s.request.owner = owner;
    s.request.axes = std::move(axes);
    EXPECT_TRUE(call(name, s));
    return s.response;
  }

  std_srvs::Trigger::Response trigger(const std::string& name) {
    std_srvs::Trigger t;
    EXPECT_TRUE(call(name, t));
    return t.response;
  }

  bool connected() const { return log_.connected(); }

  /// Drained shear for kTicks control ticks from the current (paused) state.
  Series run() {
    Series r;
    const vtm::GetInfo::Response i = info();
    r.t_start = i.time;
    r.k0 = i.tick;
    r.rate = kEpsPrime / i.t0;
    const vtm::SetStrainRate::Response sr = set_rate(2, kEpsPrime, true);
    EXPECT_TRUE(sr.success) << sr.message;
    vtm::Step st;
    st.request.count = kTicks;
    EXPECT_TRUE(call("step", st));
    EXPECT_TRUE(st.response.success) << st.response.message;
    const std::uint64_t last = r.k0 + kTicks;
    EXPECT_TRUE(wait_until([&] { return log_.has(last); }, 300.0)) << "tick " << last << " not received";
    log_.copy(r.k0 + 1, last, r.stress, r.strain);  // a missing tick shortens the series (checked by the tests)
    return r;
  }

  std::vector<ros::Time> clocks() {
    std::lock_guard<std::mutex> lock(mutex_);
    return clocks_;
  }

 private:
  void on_clock(const rosgraph_msgs::Clock::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex_);
    clocks_.push_back(m->clock);
  }

  ros::NodeHandle nh_;
  vt::rostest::StressStrainLog log_;
  ros::Subscriber clock_sub_;
  std::mutex mutex_;  // clocks_
  std::vector<ros::Time> clocks_;
};

Rig* g_rig = nullptr;
std::string g_tmp;          // temp folder for the saved start state
Series g_run_a;

bool owners_are(Rig& rig, const std::string& x, const std::string& y, const std::string& z) {
  const vtm::GetInfo::Response i = rig.info();
  return i.axis_owners[0] == x && i.axis_owners[1] == y && i.axis_owners[2] == z;
}

}  // namespace

TEST(DrainedMini, RigComesUpPausedWithTheServoOwningXAndY) {
  Rig& rig = *g_rig;
  ASSERT_TRUE(wait_until([&] { return owners_are(rig, kServo, kServo, ""); }, 60.0))
      << "the servo did not claim x and y";
  ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 30.0));
  const vtm::GetInfo::Response i = rig.info();
  EXPECT_TRUE(i.paused);
  EXPECT_TRUE(i.lockstep);
  EXPECT_EQ(i.tick, 0u);
  EXPECT_EQ(i.particles, 200u);
  EXPECT_EQ(i.publish_every, 2u);
  EXPECT_NEAR(i.dt / i.t0, i.time_step_ratio, 1e-12);
  EXPECT_NE(i.units.find("compression positive"), std::string::npos);
}

TEST(DrainedMini, BadRequestsAreRefusedNamingTheFieldAndTheNextGoodOneWorks) {
  Rig& rig = *g_rig;
  auto r = rig.set_rate(2, std::nan(""), false);
  EXPECT_FALSE(r.success);
  EXPECT_TRUE(starts_with(r.message, "strain_rate:")) << r.message;
  r = rig.set_rate(5, 1.0, false);
  EXPECT_FALSE(r.success);
  EXPECT_TRUE(starts_with(r.message, "axis:")) << r.message;
  r = rig.set_rate(2, 2e-3, true);  // above ~max_dimensionless_rate 1e-3
  EXPECT_FALSE(r.success);
  EXPECT_TRUE(starts_with(r.message, "strain_rate:")) << r.message;
  EXPECT_NE(r.message.find("max_dimensionless_rate"), std::string::npos) << r.message;
  const double t0 = rig.info().t0;
  r = rig.set_rate(2, 2e-3 / t0, false);  // the same in 1/s
  EXPECT_FALSE(r.success);
  r = rig.set_rate(0, 1e-6 / t0, false);  // owned by the servo
  EXPECT_FALSE(r.success);
  EXPECT_TRUE(starts_with(r.message, "axis:")) << r.message;
  EXPECT_NE(r.message.find(kServo), std::string::npos) << r.message;
  EXPECT_EQ(rig.info().strain_rate[2], 0.0) << "a refused request changed the rate";

  r = rig.set_rate(2, kEpsPrime, true);
  EXPECT_TRUE(r.success) << r.message;
  EXPECT_DOUBLE_EQ(rig.info().strain_rate[2], kEpsPrime / t0);

  vtm::Step step;
  step.request.count = 0;
  ASSERT_TRUE(rig.call("step", step));
  EXPECT_FALSE(step.response.success);
  EXPECT_TRUE(starts_with(step.response.message, "count:")) << step.response.message;
  vtm::SetDamping damp;
  damp.request.model = "XY";
  damp.request.ratio = 0.01;
  ASSERT_TRUE(rig.call("set_damping", damp));
  EXPECT_FALSE(damp.response.success);
  EXPECT_TRUE(starts_with(damp.response.message, "model:")) << damp.response.message;
  vtm::SetFriction fr;
  fr.request.mu = -0.1;
  ASSERT_TRUE(rig.call("set_friction", fr));
  EXPECT_FALSE(fr.response.success);
  EXPECT_TRUE(starts_with(fr.response.message, "mu:")) << fr.response.message;
  vtm::LoadSample load;
  load.request.path = g_tmp + "/does_not_exist.h5";
  ASSERT_TRUE(rig.call("load_sample", load));
  EXPECT_FALSE(load.response.success);
  EXPECT_TRUE(starts_with(load.response.message, "path:")) << load.response.message;
  EXPECT_EQ(rig.info().particles, 200u);

  vtm::SetConfiningPressure cp;
  cp.request.target = std::nan("");
  ASSERT_TRUE(rig.call("servo/set_confining_pressure", cp));
  EXPECT_FALSE(cp.response.success);
  EXPECT_TRUE(starts_with(cp.response.message, "target:")) << cp.response.message;
  cp.request.target = -1.0;
  ASSERT_TRUE(rig.call("servo/set_confining_pressure", cp));
  EXPECT_FALSE(cp.response.success);
  EXPECT_TRUE(starts_with(cp.response.message, "target:")) << cp.response.message;
  cp.request.target = kTarget;
  cp.request.ramp_seconds = -1.0;
  ASSERT_TRUE(rig.call("servo/set_confining_pressure", cp));
  EXPECT_FALSE(cp.response.success);
  EXPECT_TRUE(starts_with(cp.response.message, "ramp_seconds:")) << cp.response.message;
  cp.request.ramp_seconds = 0.0;
  ASSERT_TRUE(rig.call("servo/set_confining_pressure", cp));
  EXPECT_TRUE(cp.response.success) << cp.response.message;
}

TEST(DrainedMini, ASecondClaimIsRefusedAndReleasingFreesTheAxis) {
  Rig& rig = *g_rig;
  auto c = rig.claim_like<vtm::ClaimAxes>("claim_axes", "intruder", {0});
  EXPECT_FALSE(c.success);
  EXPECT_NE(c.message.find(kServo), std::string::npos) << c.message;
  c = rig.claim_like<vtm::ClaimAxes>("claim_axes", "intruder", {2, 0});  // all or nothing
  EXPECT_FALSE(c.success);
  EXPECT_TRUE(owners_are(rig, kServo, kServo, ""));
  auto rel = rig.claim_like<vtm::ReleaseAxes>("release_axes", "intruder", {0});
  EXPECT_FALSE(rel.success) << "released an axis it does not own";

  auto t = rig.trigger("servo/disable");
  EXPECT_TRUE(t.success) << t.message;
  EXPECT_TRUE(owners_are(rig, "", "", "")) << "disable did not release the axes (servo: " << t.message << ")";
  c = rig.claim_like<vtm::ClaimAxes>("claim_axes", "intruder", {0});
  EXPECT_TRUE(c.success) << c.message;
  EXPECT_EQ(c.tick, 0u) << "claimed while paused before the first tick";
  EXPECT_TRUE(owners_are(rig, "intruder", "", ""));
  rel = rig.claim_like<vtm::ReleaseAxes>("release_axes", "intruder", {});
  EXPECT_TRUE(rel.success) << rel.message;
  EXPECT_TRUE(owners_are(rig, "", "", ""));

  t = rig.trigger("servo/enable");
  EXPECT_TRUE(t.success) << t.message;
  EXPECT_TRUE(wait_until([&] { return owners_are(rig, kServo, kServo, ""); }, 30.0));
  EXPECT_DOUBLE_EQ(rig.info().strain_rate[2], kEpsPrime / rig.info().t0) << "z lost its open-loop rate";
}

TEST(DrainedMini, DrainedShearHoldsTheLateralStressAndFollowsTheAxialRate) {
  Rig& rig = *g_rig;
  vtm::SaveSample save;
  save.request.path = g_tmp + "/start.h5";
  ASSERT_TRUE(rig.call("save_sample", save));
  ASSERT_TRUE(save.response.success) << save.response.message;

  g_run_a = rig.run();
  const Series& r = g_run_a;
  ASSERT_EQ(r.stress.size(), kTicks);
  ASSERT_EQ(r.strain.size(), kTicks);

  double sum2 = 0;
  double prev_time = r.t_start;
  ros::Time prev_stamp(0, 0);
  for (std::size_t j = 0; j < kTicks; ++j) {
    const vtm::Stress& s = r.stress[j];
    const vtm::Strain& e = r.strain[j];
    EXPECT_EQ(s.tick, r.k0 + 1 + j);
    EXPECT_EQ(e.tick, s.tick);
    // simulation time strictly rising, in the stamp and in full precision
    EXPECT_GT(s.time, prev_time);
    EXPECT_GT(s.header.stamp, prev_stamp);
    EXPECT_EQ(e.header.stamp, s.header.stamp);
    EXPECT_NEAR(s.header.stamp.toSec(), s.time, 1e-9);
    prev_time = s.time;
    prev_stamp = s.header.stamp;
    // lateral stresses about the target
    const double ex = s.stress[0] - kTarget, ey = s.stress[4] - kTarget;
    sum2 += ex * ex + ey * ey;
    // axial log strain follows the commanded rate
    const double expected = r.rate * (e.time - r.t_start);
    EXPECT_NEAR(e.strain[2], expected, 1e-6 * expected) << "tick " << e.tick;
    EXPECT_DOUBLE_EQ(e.strain_rate[2], r.rate);
    EXPECT_NEAR(e.strain_rate_dimensionless[2], kEpsPrime, 1e-15);
  }
  const double rms = std::sqrt(sum2 / (2.0 * kTicks)) / kTarget;
  std::printf("[drained_mini] lateral stress RMS error %.4f %% of %.0f Pa over %u ticks; "
              "axial strain %.3e; q %.1f kPa at the end\n",
              100.0 * rms, kTarget, kTicks, r.strain.back().strain[2], r.stress.back().q / 1e3);
  EXPECT_LT(rms, 0.01) << "lateral stresses not within 1 % RMS of the target (ASTM D4767)";
  EXPECT_GT(r.stress.back().q, 20e3) << "the sample was not sheared";
  EXPECT_GT(r.stress.back().stress[8], r.stress.front().stress[8]);

  const vtm::GetInfo::Response i = rig.info();
  EXPECT_EQ(i.tick, r.k0 + kTicks);
  EXPECT_TRUE(i.paused);
  EXPECT_EQ(i.lockstep_timeouts, 0u) << "a lockstep timeout makes the run depend on timing";
  EXPECT_EQ(i.rejected_commands, 0u);
  EXPECT_DOUBLE_EQ(i.time, r.stress.back().time);
  // /clock carries the simulation time
  ASSERT_TRUE(wait_until([&] { return !rig.clocks().empty() && rig.clocks().back() == r.stress.back().header.stamp; },
                         10.0));
}

TEST(DrainedMini, ALockstepRunIsBitIdenticalWhenRepeated) {
  Rig& rig = *g_rig;
  ASSERT_EQ(g_run_a.stress.size(), kTicks) << "run A failed";
  vtm::LoadSample load;
  load.request.path = g_tmp + "/start.h5";
  ASSERT_TRUE(rig.call("load_sample", load));
  ASSERT_TRUE(load.response.success) << load.response.message;
  EXPECT_DOUBLE_EQ(rig.info().time, g_run_a.t_start);

  const Series b = rig.run();
  ASSERT_EQ(b.stress.size(), kTicks);
  ASSERT_EQ(b.strain.size(), kTicks);
  EXPECT_EQ(b.k0, g_run_a.k0 + kTicks) << "ticks keep counting across loads";
  std::size_t differing = 0;
  for (std::size_t j = 0; j < kTicks; ++j) {
    const vtm::Stress& a = g_run_a.stress[j];
    const vtm::Stress& s = b.stress[j];
    const bool same = std::memcmp(a.stress.data(), s.stress.data(), sizeof(double) * 9) == 0 &&
                      std::memcmp(a.stiffness.data(), s.stiffness.data(), sizeof(double) * 3) == 0 &&
                      std::memcmp(&a.time, &s.time, sizeof(double)) == 0 &&
                      std::memcmp(g_run_a.strain[j].strain.data(), b.strain[j].strain.data(), sizeof(double) * 3) == 0;
    if (!same && differing++ == 0)
      ADD_FAILURE() << "first difference at tick " << j + 1 << " of the run: sigma_xx " << a.stress[0] << " vs "
                    << s.stress[0];
  }
  EXPECT_EQ(differing, 0u) << "ticks whose stress/strain differ between the two runs";
  EXPECT_EQ(rig.info().lockstep_timeouts, 0u);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_drained_mini");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  char tmpl[] = "/tmp/vt_drained_mini_XXXXXX";
  const char* dir = mkdtemp(tmpl);
  if (!dir) return 2;
  g_tmp = dir;
  Rig rig;
  g_rig = &rig;
  const int rc = RUN_ALL_TESTS();
  std::remove((g_tmp + "/start.h5").c_str());
  rmdir(g_tmp.c_str());
  spinner.stop();
  ros::shutdown();
  return rc;
}
