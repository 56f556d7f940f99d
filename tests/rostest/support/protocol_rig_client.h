// The client side of the rostest protocol_rig.test (test_protocol_rig.cpp):
// the Rig that sends run_test goals and records the stress, strain and
// protocol_status of every tick, what one goal gave (TestRun), and the
// checks several tests share (sane summary, rising stamps, the same summary
// as the headless triax_run on the same protocol, a run beside CPU hogs).
// Included by test_protocol_rig.cpp and test_protocol_rig_slow_claim.cpp
// (run_rig_tests() is their main: ~protocols, ~sample, scratch folder).
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <yaml-cpp/yaml.h>

#include "virtual_triaxial/GetInfo.h"
#include "virtual_triaxial/ProtocolStatus.h"
#include "virtual_triaxial/RunTestAction.h"
#include "virtual_triaxial/Strain.h"
#include "virtual_triaxial/Stress.h"

#include "rig_test_helpers.h"
#include "stress_strain_log.h"

namespace vtm = virtual_triaxial;
namespace fs = std::filesystem;
using Client = actionlib::SimpleActionClient<vtm::RunTestAction>;

using vt::rostest::starts_with;
using vt::rostest::wait_until;

namespace {

constexpr double kPressure = 100e3;     // confining pressure of the protocols [Pa]
constexpr double kTarget = 0.01;        // axial strain target of drained_mini / undrained_mini
constexpr double kEpsPrime = 1e-5;      // eps' of the shears
constexpr double kTimeStepRatio = 0.1;  // c_t (0.3 gives a 1.2 % servo lag)
constexpr int kInterval = 2;            // control.interval = publish_every
/// Axial log strain of one control tick: eps' dt/T0 * interval.
constexpr double kTickStrain = kEpsPrime * kTimeStepRatio * kInterval;
constexpr double kRunTimeout = 120.0;   // wall seconds for one mini test

std::string g_protocols, g_sample, g_tmp;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }


std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream o;
  o << f.rdbuf();
  return o.str();
}

std::string fmt9(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", x);
  return b;
}

/// The folder of this executable (build/devel/lib/virtual_triaxial), where
/// triax_run is built too.
fs::path exe_dir() { return fs::read_symlink("/proc/self/exe").parent_path(); }

/// What one goal gave.
struct TestRun {
  bool finished = false;
  actionlib::SimpleClientGoalState state{actionlib::SimpleClientGoalState::LOST};
  vtm::RunTestResult result;
  double wall = 0;                  ///< wall seconds until the result
  std::uint64_t first = 0, last = 0;  ///< ticks of the run: [first, last]
  std::map<std::string, std::uint64_t> stage_end;  ///< last tick of each stage (protocol_status)
  std::vector<vtm::Stress> stress;  ///< by tick, first..last
  std::vector<vtm::Strain> strain;
  std::vector<vtm::ProtocolStatus> status;

  /// Stress/strain index range (begin, end) of the ticks (from, to].
  std::pair<std::size_t, std::size_t> range(std::uint64_t from, std::uint64_t to) const {
    return {static_cast<std::size_t>(from + 1 - first), static_cast<std::size_t>(to + 1 - first)};
  }
};

class Rig {
 public:
  Rig() : client_("run_test", false), log_(nh_) {
    status_sub_ = nh_.subscribe("protocol_status", 100000, &Rig::on_status, this);
  }

  bool ready() {
    return wait_until([&] { return client_.isServerConnected(); }, 60.0) &&
           wait_until([&] { return log_.connected() && status_sub_.getNumPublishers() > 0; },
                      30.0);
  }

  template <class S>
  bool call(const std::string& name, S& srv) {
    return vt::rostest::call_service(name, srv, 30.0);
  }

  vtm::GetInfo::Response info() {
    vtm::GetInfo s;
    EXPECT_TRUE(vt::rostest::call_service_again("get_info", s, 30.0));
    return s.response;
  }

  std_srvs::Trigger::Response abort() {
    std_srvs::Trigger t;
    EXPECT_TRUE(call("/test_protocol_node/abort", t));
    return t.response;
  }

  /// Sends `goal`; `during` (if any) runs while it executes; waits for the
  /// result (wall time) and collects the messages of its ticks.
  TestRun run(const vtm::RunTestGoal& goal, double timeout = kRunTimeout,
          const std::function<void(Client&)>& during = {}) {
    log_.clear();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      status_.clear();
    }
    TestRun r;
    const ros::WallTime t0 = ros::WallTime::now();
    client_.sendGoal(goal);
    if (during) during(client_);
    r.finished = wait_until([&] { return client_.getState().isDone(); }, timeout);
    r.wall = (ros::WallTime::now() - t0).toSec();
    if (!r.finished) {
      client_.cancelGoal();
      wait_until([&] { return client_.getState().isDone(); }, 30.0);
      return r;
    }
    r.state = client_.getState();
    if (vtm::RunTestResultConstPtr res = client_.getResult()) r.result = *res;
    if (r.result.ticks == 0) return r;
    r.last = info().tick;  // the rig halts right after the last tick of the test
    r.first = r.last - r.result.ticks + 1;
    // the state of the last tick may still be on its way
    EXPECT_TRUE(wait_until([&] { return log_.has(r.last); }, 10.0)) << "no stress/strain for tick " << r.last;
    wait_until([&] { return last_status_done(); }, 5.0);
    const std::uint64_t missing = log_.copy(r.first, r.last, r.stress, r.strain);
    if (missing <= r.last) ADD_FAILURE() << "tick " << missing << " of the run not received";
    std::lock_guard<std::mutex> lock(mutex_);
    r.status = status_;
    for (const vtm::ProtocolStatus& s : status_)
      if (!s.stage.empty() && s.tick > 0 && s.tick > r.stage_end[s.stage]) r.stage_end[s.stage] = s.tick;
    return r;
  }

 private:
  bool last_status_done() {
    std::lock_guard<std::mutex> lock(mutex_);
    return !status_.empty() && status_.back().state != "running";
  }
  void on_status(const vtm::ProtocolStatus::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex_);
    status_.push_back(*m);
  }

  ros::NodeHandle nh_;
  Client client_;
  vt::rostest::StressStrainLog log_;
  ros::Subscriber status_sub_;
  std::mutex mutex_;  // status_
  std::vector<vtm::ProtocolStatus> status_;
};

Rig* g_rig = nullptr;
TestRun g_drained;  // run of test 1, the reference of test 3

vtm::RunTestGoal file_goal(const std::string& protocol, const std::string& out) {
  vtm::RunTestGoal g;
  g.protocol_file = g_protocols + "/" + protocol;
  g.output_dir = g_tmp + "/" + out;
  return g;
}

/// Sanity of a completed drained/undrained mini run (result + files).
void expect_sane_summary(const TestRun& r) {
  const vtm::RunTestResult& s = r.result;
  EXPECT_GT(s.e0, 0.4);
  EXPECT_LT(s.e0, 1.0);
  EXPECT_GT(s.phi_peak, 0.0);
  EXPECT_LT(s.phi_peak, 60.0 * M_PI / 180.0);
  EXPECT_GE(s.eps_peak, 0.0);
  EXPECT_LE(s.eps_peak, kTarget + kTickStrain * 1.01) << "peak beyond the last tick";
  EXPECT_GT(s.mean_moment_index, 0.0);
  EXPECT_TRUE(std::isfinite(s.mean_moment_index));
  EXPECT_GT(s.runtime, 0.0);
  EXPECT_LE(s.runtime, r.wall + 1.0);
  EXPECT_GT(s.ticks, 0u);
  EXPECT_EQ(s.steps, static_cast<std::int64_t>(kInterval * s.ticks));
  EXPECT_EQ(s.stages.size(), s.stop_reasons.size());
  EXPECT_TRUE(fs::is_regular_file(s.results_file)) << s.results_file;
  EXPECT_GT(fs::file_size(s.results_file), 0u);
  ASSERT_TRUE(fs::is_regular_file(s.summary_file)) << s.summary_file;
  YAML::Node j;  // JSON is YAML
  ASSERT_NO_THROW(j = YAML::Load(slurp(s.summary_file))) << slurp(s.summary_file);
  ASSERT_TRUE(j.IsMap());
  EXPECT_EQ(j["verdict"].as<std::string>(), "completed");
  EXPECT_EQ(j["steps"].as<std::int64_t>(), s.steps);
  EXPECT_EQ(j["ticks"].as<std::uint64_t>(), s.ticks);
  EXPECT_EQ(j["particles"].as<int>(), 200);
  EXPECT_EQ(j["stages"].size(), s.stages.size());
  for (const char* key : {"e0", "phi_peak_deg", "eps_peak", "q_peak_pa", "phi_end_deg", "eps_end", "p_end_pa",
                          "q_end_pa", "mean_moment_index_to_peak", "max_moment_index_to_peak",
                          "quasi_static_threshold", "strain_rate_dimensionless_min", "strain_rate_dimensionless_max",
                          "wall_seconds", "t0_s", "dt_s"}) {
    ASSERT_TRUE(j[key] && j[key].IsScalar()) << "summary.json lacks " << key;
    EXPECT_TRUE(std::isfinite(j[key].as<double>())) << key;
  }
  EXPECT_EQ(j["quasi_static"].as<bool>(), s.quasi_static);
  EXPECT_EQ(s.quasi_static, s.mean_moment_index < s.quasi_static_threshold);
  // a fixed rate: the range is one value, the mean below the largest sample
  EXPECT_EQ(s.rate_strategy, "fixed");
  EXPECT_EQ(j["rate_strategy"].as<std::string>(), "fixed");
  EXPECT_GT(s.strain_rate_dimensionless_min, 0.0);
  EXPECT_EQ(s.strain_rate_dimensionless_min, s.strain_rate_dimensionless_max);
  EXPECT_LE(s.mean_moment_index, s.max_moment_index);
  EXPECT_GT(s.quasi_static_threshold, 0.0);
  EXPECT_GT(s.phi_end, 0.0);
  EXPECT_LE(s.phi_end, s.phi_peak);
  EXPECT_EQ(j["results"].as<std::string>(), s.results_file);
  EXPECT_EQ(s.stop_reasons.size(), s.stages.size());
  for (const std::string& why : s.stop_reasons) EXPECT_FALSE(why.empty());
}

/// Stamps (header and full-precision time) strictly rising over the run.
void expect_stamps_rising(const TestRun& r) {
  for (std::size_t j = 1; j < r.stress.size(); ++j) {
    EXPECT_GT(r.stress[j].header.stamp, r.stress[j - 1].header.stamp) << "tick " << r.stress[j].tick;
    EXPECT_GT(r.stress[j].time, r.stress[j - 1].time) << "tick " << r.stress[j].tick;
    EXPECT_EQ(r.strain[j].header.stamp, r.stress[j].header.stamp);
  }
  ros::Time prev(0, 0);
  std::uint64_t prev_tick = 0;
  for (const vtm::ProtocolStatus& s : r.status) {
    if (s.state != "running" || s.tick == 0) continue;
    if (s.tick > prev_tick) {
      EXPECT_GT(s.header.stamp, prev) << "status of tick " << s.tick;
    } else {
      EXPECT_EQ(s.tick, prev_tick) << "protocol_status ticks going back";
    }
    prev = s.header.stamp;
    prev_tick = s.tick;
  }
}

/// `run()` with two busy threads beside it (the rig must stay deterministic).
template <class Run>
auto under_cpu_load(Run run) {
  std::atomic<bool> stop{false};
  std::vector<std::thread> hogs;
  for (int i = 0; i < 2; ++i)
    hogs.emplace_back([&stop] {
      volatile std::uint64_t x = 0;
      while (!stop.load(std::memory_order_relaxed)) x = x + 1;
    });
  auto result = run();
  stop = true;
  for (std::thread& t : hogs) t.join();
  return result;
}

/// Runs `protocol` headless (triax_run) and expects the rig's summary of run
/// `r` to equal its, number for number (the same decisions, tick for tick).
void expect_same_as_triax_run(const TestRun& r, const std::string& protocol, const std::string& dir) {
  const fs::path triax_run = exe_dir() / "triax_run";
  ASSERT_TRUE(fs::exists(triax_run)) << triax_run << " not built (make all)";
  const fs::path out = fs::path(g_tmp) / dir;
  fs::create_directories(out);
  const std::string cmd = triax_run.string() + " " + g_protocols + "/" + protocol + " --quiet --out " +
                          (out / "results.h5").string() + " >" + (out / "stdout.txt").string() + " 2>" +
                          (out / "stderr.txt").string();
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd << "\n" << slurp(out / "stderr.txt");
  std::string stdout_text = slurp(out / "stdout.txt"), line;
  std::istringstream lines(stdout_text);
  for (std::string l; std::getline(lines, l);)
    if (!l.empty()) line = l;
  YAML::Node h, rj;
  ASSERT_NO_THROW(h = YAML::Load(line)) << line;
  ASSERT_NO_THROW(rj = YAML::Load(slurp(r.result.summary_file)));
  EXPECT_EQ(h["verdict"].as<std::string>(), "completed");
  for (const char* key : {"e0", "phi_peak_deg", "eps_peak", "mean_moment_index_to_peak", "max_moment_index_to_peak",
                          "phi_end_deg", "q_peak_pa", "rate_strategy", "strain_rate_dimensionless_min",
                          "strain_rate_dimensionless_max", "quasi_static"})
    EXPECT_EQ(rj[key].Scalar(), h[key].Scalar()) << key << ": rig vs triax_run";
  const double deg = 180.0 / M_PI;
  EXPECT_EQ(fmt9(r.result.e0), h["e0"].Scalar());
  EXPECT_EQ(fmt9(r.result.phi_peak * deg), h["phi_peak_deg"].Scalar());
  EXPECT_EQ(fmt9(r.result.eps_peak), h["eps_peak"].Scalar());
  EXPECT_EQ(fmt9(r.result.mean_moment_index), h["mean_moment_index_to_peak"].Scalar());
  EXPECT_EQ(h["steps"].as<std::int64_t>(), r.result.steps);
  EXPECT_EQ(h["ticks"].as<std::uint64_t>(), r.result.ticks);
}

/// The test node's main: ~protocols and ~sample from the .test, a scratch
/// folder, one Rig for every test of the binary.
int run_rig_tests(int argc, char** argv, const char* name) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, name);
  ros::NodeHandle nh, pnh("~");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  if (!pnh.getParam("protocols", g_protocols) || !pnh.getParam("sample", g_sample)) {
    std::fprintf(stderr, "%s: ~protocols and ~sample must be set (see its .test)\n", name);
    return 2;
  }
  char tmpl[] = "/tmp/vt_protocol_rig_XXXXXX";
  const char* dir = mkdtemp(tmpl);
  if (!dir) return 2;
  g_tmp = dir;
  int rc = 0;
  {
    Rig rig;
    g_rig = &rig;
    rc = RUN_ALL_TESTS();
    g_rig = nullptr;
  }
  std::error_code ec;
  fs::remove_all(g_tmp, ec);
  spinner.stop();
  ros::shutdown();
  return rc;
}

}  // namespace
