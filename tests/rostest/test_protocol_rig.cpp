// rostest protocol_rig.test: test_protocol_node on the rig of
// launch_equiv_scripts/protocol_rig.launch (dem_node paused, servo "servo"
// disabled), driven through the run_test action with the small protocols of
// tests/data/protocols/ on the 200-sphere sample tests/data/sample_200_100kPa.h5.
//
// The tests run in order (gtest keeps the order of definition) against one rig:
//   1. drained mini test (consolidation + drained shear to 1 %): completed,
//      lateral stresses within 1 % RMS of 100 kPa during the shear (ASTM
//      D4767), target strain reached within one tick, summary sane, files
//      written, stamps strictly rising; the headless triax_run on the same file
//      prints the same e0, phi_peak, eps_peak, mean I_mom (9 digits);
//   2. undrained mini test: the cell volume is constant on every tick;
//   3. lockstep determinism: the drained mini test again with two CPU hogs
//      beside it gives a bit-identical stress series;
//   4. preemption: cancelling a long test ends it within seconds, verdict
//      "preempted", summary written, rig paused; ~abort gives "aborted";
//      ~abort when idle is refused;
//   5. bad goals (two protocols, bad stage type, wrong control.interval) are
//      refused naming the field, the node keeps serving: an inline YAML goal
//      completes.
// Goals are stamped with the simulation time, which restarts at every
// load_sample: from test 3 on, goals are stamped before the previous goal
// (test 2 ends at an earlier simulation time than test 1), which
// actionlib's SimpleActionServer used to recall.
//
// The rig runs on simulation time (/use_sim_time), which stands still while
// dem_node is paused: every wait here is in wall time.
#include "../unit/support/run_limits_cases.h"

#include <cstdio>
#include <string>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <yaml-cpp/yaml.h>

#include "support/protocol_rig_client.h"

TEST(ProtocolRig, DrainedMiniTestCompletesHoldsTheLateralStressAndMatchesTriaxRun) {
  Rig& rig = *g_rig;
  ASSERT_TRUE(rig.ready()) << "no run_test action server / rig topics";
  const vtm::GetInfo::Response i0 = rig.info();
  EXPECT_TRUE(i0.paused);
  EXPECT_EQ(i0.publish_every, static_cast<std::uint32_t>(kInterval));

  g_drained = rig.run(file_goal("drained_mini.yaml", "drained"));
  const TestRun& r = g_drained;
  ASSERT_TRUE(r.finished) << "no result within " << kRunTimeout << " s";
  std::printf("[protocol_rig] drained mini: %s in %.1f s wall, %llu ticks\n", r.result.verdict.c_str(), r.wall,
              static_cast<unsigned long long>(r.result.ticks));
  EXPECT_EQ(r.state, actionlib::SimpleClientGoalState::SUCCEEDED);
  ASSERT_EQ(r.result.verdict, "completed") << r.result.message;
  ASSERT_EQ(r.result.stages, (std::vector<std::string>{"consolidation", "shear"}));
  ASSERT_EQ(r.stress.size(), r.result.ticks);
  ASSERT_EQ(r.strain.size(), r.result.ticks);
  for (std::size_t j = 0; j < r.stress.size(); ++j) ASSERT_EQ(r.stress[j].tick, r.first + j);
  expect_sane_summary(r);
  expect_stamps_rising(r);

  // the shear stage: ticks (end of consolidation, end of shear]
  ASSERT_TRUE(r.stage_end.count("consolidation") && r.stage_end.count("shear"));
  EXPECT_EQ(r.stage_end.at("shear"), r.last);
  const auto [b, e] = r.range(r.stage_end.at("consolidation"), r.stage_end.at("shear"));
  ASSERT_GT(e, b + 20) << "shear stage too short";
  constexpr std::size_t kSkip = 5;  // the servo takes over the lateral axes
  double sum2 = 0;
  std::size_t n = 0;
  for (std::size_t j = b + kSkip; j < e; ++j) {
    const double ex = r.stress[j].stress[0] - kPressure, ey = r.stress[j].stress[4] - kPressure;
    sum2 += ex * ex + ey * ey;
    n += 2;
  }
  const double rms = std::sqrt(sum2 / static_cast<double>(n)) / kPressure;
  const double eps_end = r.strain[e - 1].strain[2], eps_before = r.strain[e - 2].strain[2];
  std::printf("[protocol_rig] shear: %zu ticks, lateral stress RMS error %.3f %%, eps_a %.6f at the end\n", e - b,
              100 * rms, eps_end);
  EXPECT_LT(rms, 0.01) << "lateral stresses not within 1 % RMS of the confining pressure (ASTM D4767)";
  EXPECT_GE(eps_end, kTarget) << "target axial strain not reached";
  EXPECT_LT(eps_before, kTarget) << "the stage went on after reaching the target";
  EXPECT_LE(eps_end - kTarget, kTickStrain * 1.01) << "stopped more than one tick late";
  EXPECT_NEAR(r.strain[b].strain[2], kTickStrain, 0.01 * kTickStrain) << "strain not reset at the stage start";
  const vtm::GetInfo::Response i1 = rig.info();
  EXPECT_TRUE(i1.paused);
  EXPECT_EQ(i1.lockstep_timeouts, 0u);
  EXPECT_EQ(i1.axis_owners[0], "");
  EXPECT_EQ(i1.axis_owners[2], "");

  expect_same_as_triax_run(r, "drained_mini.yaml", "headless");
}

TEST(ProtocolRig, UndrainedMiniTestKeepsTheCellVolumeConstant) {
  Rig& rig = *g_rig;
  const TestRun r = rig.run(file_goal("undrained_mini.yaml", "undrained"));
  ASSERT_TRUE(r.finished);
  std::printf("[protocol_rig] undrained mini: %s in %.1f s wall, %llu ticks\n", r.result.verdict.c_str(), r.wall,
              static_cast<unsigned long long>(r.result.ticks));
  ASSERT_EQ(r.result.verdict, "completed") << r.result.message;
  ASSERT_EQ(r.result.stages, std::vector<std::string>{"undrained"});
  ASSERT_EQ(r.strain.size(), r.result.ticks);
  expect_sane_summary(r);
  double worst = 0;
  for (const vtm::Strain& s : r.strain) {
    EXPECT_LE(std::abs(s.volumetric), 1e-9) << "tick " << s.tick;
    worst = std::max(worst, std::abs(s.volumetric));
  }
  std::printf("[protocol_rig] undrained: max |eps_v| %.3g over %zu ticks, eps_a %.6f at the end\n", worst,
              r.strain.size(), r.strain.back().strain[2]);
  EXPECT_GE(r.strain.back().strain[2], kTarget);
}

TEST(ProtocolRig, ARunUnderCpuLoadIsBitIdentical) {
  Rig& rig = *g_rig;
  ASSERT_EQ(g_drained.result.verdict, "completed") << "run of test 1 missing";
  const TestRun b = under_cpu_load([&] { return rig.run(file_goal("drained_mini.yaml", "drained_loaded")); });
  ASSERT_TRUE(b.finished);
  std::printf("[protocol_rig] drained mini under load: %s in %.1f s wall (%.1f s unloaded)\n",
              b.result.verdict.c_str(), b.wall, g_drained.wall);
  ASSERT_EQ(b.result.verdict, "completed") << b.result.message;
  const TestRun& a = g_drained;
  ASSERT_EQ(b.stress.size(), a.stress.size());
  ASSERT_EQ(b.result.ticks, a.result.ticks);
  std::size_t differing = 0;
  for (std::size_t j = 0; j < a.stress.size(); ++j) {
    const vtm::Stress &x = a.stress[j], &y = b.stress[j];
    const bool same = std::memcmp(x.stress.data(), y.stress.data(), sizeof(double) * 9) == 0 &&
                      std::memcmp(&x.q, &y.q, sizeof(double)) == 0 &&
                      std::memcmp(&x.time, &y.time, sizeof(double)) == 0;
    if (!same && differing++ == 0)
      ADD_FAILURE() << "first difference at tick " << j + 1 << " of the run: sxx " << x.stress[0] << " vs "
                    << y.stress[0] << ", q " << x.q << " vs " << y.q;
  }
  EXPECT_EQ(differing, 0u) << "ticks whose stress differs between the runs";
  EXPECT_EQ(fmt9(a.result.phi_peak), fmt9(b.result.phi_peak));
  EXPECT_EQ(rig.info().lockstep_timeouts, 0u);
}

TEST(ProtocolRig, CancelPreemptsAndAbortAborts) {
  Rig& rig = *g_rig;
  // cancel after ~2 s
  const TestRun p = rig.run(file_goal("drained_long.yaml", "preempted"), 60.0, [&](Client& c) {
    ros::WallDuration(2.0).sleep();
    c.cancelGoal();
  });
  ASSERT_TRUE(p.finished) << "no result after cancelling";
  std::printf("[protocol_rig] preempted run: result %.2f s after the goal (%llu ticks)\n", p.wall,
              static_cast<unsigned long long>(p.result.ticks));
  EXPECT_LT(p.wall, 2.0 + 5.0) << "the result came too late after the cancel";
  EXPECT_EQ(p.state, actionlib::SimpleClientGoalState::PREEMPTED);
  EXPECT_EQ(p.result.verdict, "preempted") << p.result.message;
  EXPECT_FALSE(p.result.stages.empty());
  EXPECT_EQ(p.result.stop_reasons.size(), p.result.stages.size());
  if (!p.result.stop_reasons.empty()) {
    EXPECT_EQ(p.result.stop_reasons.back(), "preempted");
  }
  EXPECT_GT(p.result.ticks, 0u);
  EXPECT_LT(p.strain.empty() ? 1.0 : p.strain.back().strain[2], 0.5) << "the test was not cut short";
  ASSERT_TRUE(fs::is_regular_file(p.result.summary_file));
  const std::string js = slurp(p.result.summary_file);
  YAML::Node j;
  ASSERT_NO_THROW(j = YAML::Load(js)) << js;
  EXPECT_EQ(j["verdict"].as<std::string>(), "preempted") << js;
  EXPECT_TRUE(contains(j["failure"].as<std::string>(""), "preempted")) << js;
  EXPECT_TRUE(fs::is_regular_file(p.result.results_file));
  vtm::GetInfo::Response i = rig.info();
  EXPECT_TRUE(i.paused) << "the rig runs on after the preemption";
  EXPECT_EQ(i.tick, p.last);

  // ~abort during another long run; a second goal meanwhile is rejected
  std_srvs::Trigger::Response ab;
  Client second("run_test", false);
  actionlib::SimpleClientGoalState second_state(actionlib::SimpleClientGoalState::LOST);
  vtm::RunTestResult second_result;
  const TestRun a = rig.run(file_goal("drained_long.yaml", "aborted"), 60.0, [&](Client&) {
    ros::WallDuration(1.0).sleep();
    if (wait_until([&] { return second.isServerConnected(); }, 10.0)) {
      second.sendGoal(file_goal("drained_mini.yaml", "second"));
      if (wait_until([&] { return second.getState().isDone(); }, 10.0)) {
        second_state = second.getState();
        if (second.getResult()) second_result = *second.getResult();
      }
    }
    ros::WallDuration(1.0).sleep();
    ab = rig.abort();
  });
  EXPECT_EQ(second_state, actionlib::SimpleClientGoalState::REJECTED) << "a goal during a test";
  EXPECT_EQ(second_result.verdict, "failed");
  EXPECT_TRUE(contains(second_result.message, "goal")) << second_result.message;
  ASSERT_TRUE(a.finished) << "no result after ~abort";
  EXPECT_TRUE(ab.success) << ab.message;
  EXPECT_LT(a.wall, 2.0 + 5.0);
  EXPECT_EQ(a.state, actionlib::SimpleClientGoalState::ABORTED);
  EXPECT_EQ(a.result.verdict, "aborted") << a.result.message;
  EXPECT_FALSE(a.result.stages.empty());
  ASSERT_TRUE(fs::is_regular_file(a.result.summary_file));
  EXPECT_TRUE(contains(slurp(a.result.summary_file), "aborted"));
  i = rig.info();
  EXPECT_TRUE(i.paused);

  // ~abort when idle
  const std_srvs::Trigger::Response idle = rig.abort();
  EXPECT_FALSE(idle.success);
  EXPECT_FALSE(idle.message.empty());
}

TEST(ProtocolRig, BadGoalsAreRefusedNamingTheFieldAndTheNodeKeepsServing) {
  Rig& rig = *g_rig;
  const std::uint64_t tick0 = rig.info().tick;
  {
    vtm::RunTestGoal g = file_goal("drained_mini.yaml", "bad_both");
    g.protocol_yaml = slurp(g.protocol_file);
    const TestRun r = rig.run(g, 30.0);
    ASSERT_TRUE(r.finished);
    EXPECT_EQ(r.state, actionlib::SimpleClientGoalState::ABORTED);
    EXPECT_EQ(r.result.verdict, "failed");
    EXPECT_TRUE(contains(r.result.message, "goal")) << r.result.message;
  }
  {
    const TestRun r = rig.run(vtm::RunTestGoal(), 30.0);  // no protocol at all
    ASSERT_TRUE(r.finished);
    EXPECT_EQ(r.result.verdict, "failed");
    EXPECT_TRUE(contains(r.result.message, "goal")) << r.result.message;
  }
  {
    const TestRun r = rig.run(file_goal("bad_stage_type.yaml", "bad_type"), 30.0);
    ASSERT_TRUE(r.finished);
    EXPECT_EQ(r.result.verdict, "failed");
    EXPECT_TRUE(contains(r.result.message, "stages[0].type")) << r.result.message;
  }
  {
    const TestRun r = rig.run(file_goal("bad_interval.yaml", "bad_interval"), 30.0);
    ASSERT_TRUE(r.finished);
    EXPECT_EQ(r.result.verdict, "failed");
    EXPECT_TRUE(contains(r.result.message, "control.interval")) << r.result.message;
  }
  const vtm::GetInfo::Response i = rig.info();
  EXPECT_EQ(i.tick, tick0) << "a refused goal ran the rig";
  EXPECT_TRUE(i.paused);

  // the next good goal: inline YAML with an absolute sample path
  std::string yaml = slurp(g_protocols + "/drained_mini.yaml");
  const std::string rel = "../sample_200_100kPa.h5";
  const std::size_t at = yaml.find(rel);
  ASSERT_NE(at, std::string::npos);
  yaml.replace(at, rel.size(), g_sample);
  vtm::RunTestGoal g;
  g.protocol_yaml = yaml;
  g.output_dir = g_tmp + "/inline";
  const TestRun r = rig.run(g);
  ASSERT_TRUE(r.finished);
  EXPECT_EQ(r.state, actionlib::SimpleClientGoalState::SUCCEEDED);
  ASSERT_EQ(r.result.verdict, "completed") << r.result.message;
  expect_sane_summary(r);
  EXPECT_TRUE(fs::is_regular_file(g.output_dir + "/protocol.yaml"));
  // same protocol as test 1: the same test
  EXPECT_EQ(r.result.ticks, g_drained.result.ticks);
  EXPECT_EQ(fmt9(r.result.phi_peak), fmt9(g_drained.result.phi_peak));
}

// The limits of io/run_limits.h: the table tests/data/run_limits_cases.yaml
// (bad rates, c_t values and a particle count), which test_triax_run_cli
// feeds to triax_run, goes to both runners here: each refuses it before it
// runs, the rig with the same line as triax_run, and that line is the
// table's.
TEST(ProtocolRig, RunLimitsRefuseTheSameValuesAsTriaxRun) {
  Rig& rig = *g_rig;
  const std::uint64_t tick0 = rig.info().tick;
  const auto cases = vt::test::run_limits_cases(fs::path(g_protocols).parent_path().string(), g_sample);
  ASSERT_GE(cases.size(), 5u);
  for (const auto& c : cases) {
    const fs::path file = fs::path(g_tmp) / ("limits_" + c.name + ".yaml");
    std::ofstream(file) << c.yaml;
    const fs::path err = fs::path(g_tmp) / ("limits_" + c.name + ".err");
    const std::string cmd = (exe_dir() / "triax_run").string() + " " + file.string() + " --quiet --out " + g_tmp +
                            "/limits_" + c.name + ".h5 > /dev/null 2> " + err.string();
    const int status = std::system(cmd.c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2) << c.name;
    std::string headless = slurp(err);
    const std::string prefix = "triax_run: error: ";
    ASSERT_EQ(headless.rfind(prefix, 0), 0u) << c.name << ": " << headless;
    headless = headless.substr(prefix.size());
    while (!headless.empty() && headless.back() == '\n') headless.pop_back();
    EXPECT_EQ(headless.rfind(c.message, 0), 0u) << c.name << ": triax_run '" << headless << "'";
    vtm::RunTestGoal g;
    g.protocol_yaml = c.yaml;
    g.output_dir = g_tmp + "/limits_" + c.name;
    const TestRun r = rig.run(g, 60.0);
    ASSERT_TRUE(r.finished) << c.name;
    EXPECT_EQ(r.result.verdict, "failed") << c.name;
    EXPECT_EQ(r.result.message, "protocol: " + headless) << c.name << ": the rig and triax_run refuse alike";
  }
  const vtm::GetInfo::Response i = rig.info();
  EXPECT_TRUE(i.paused) << "a refused goal left the rig running";
  EXPECT_LE(i.tick, tick0 + 1) << "a refused goal ran the rig";
}

int main(int argc, char** argv) { return run_rig_tests(argc, argv, "test_protocol_rig"); }

// The adaptive rate strategy on the rig: the protocol node configures and
// enables the rate controller (rate_controller_node; py_rate_controller.py in
// protocol_rig_python.test), which commands the axial rate every tick from
// I_mom. Run with two CPU hogs beside it, the rig must still take the
// headless triax_run's decisions tick for tick: the same summary, including
// the range of eps' the law used (which must span more than one rate).
TEST(ProtocolRig, AdaptiveRateControllerTakesTriaxRunsDecisionsUnderLoad) {
  Rig& rig = *g_rig;
  ASSERT_TRUE(rig.ready()) << "no run_test action server / rig topics";
  const TestRun r = under_cpu_load([&] { return rig.run(file_goal("adaptive_mini.yaml", "adaptive")); });
  ASSERT_TRUE(r.finished) << "no result within " << kRunTimeout << " s";
  std::printf("[protocol_rig] adaptive mini under load: %s in %.1f s wall, %llu ticks\n", r.result.verdict.c_str(),
              r.wall, static_cast<unsigned long long>(r.result.ticks));
  ASSERT_EQ(r.result.verdict, "completed") << r.result.message;
  YAML::Node rj;
  ASSERT_NO_THROW(rj = YAML::Load(slurp(r.result.summary_file)));
  EXPECT_EQ(rj["rate_strategy"].as<std::string>(), "adaptive");
  const double lo = rj["strain_rate_dimensionless_min"].as<double>(), hi = rj["strain_rate_dimensionless_max"].as<double>();
  std::printf("[protocol_rig] adaptive eps' range %.4g .. %.4g\n", lo, hi);
  EXPECT_GT(hi, 1.2 * lo) << "the adaptive law never changed the rate";
  const vtm::GetInfo::Response i1 = rig.info();
  EXPECT_EQ(i1.lockstep_timeouts, 0u);
  EXPECT_EQ(i1.axis_owners[2], "") << "the rate controller kept the axial axis after the test";
  expect_same_as_triax_run(r, "adaptive_mini.yaml", "headless_adaptive");
}
