// Test-protocol stages, headless (protocol/stage_spec.h, stage_monitor.h,
// stage_runner.h) and their YAML keys (io/scene_parser.h):
//   - stage boundaries: which axes are servo-held, open-loop rates (undrained
//     log rates sum to zero);
//   - StageMonitor: softening after the peak, balanced (servo axes within the
//     tolerance AND UFR below), UFR criteria only on sample ticks;
//   - servo consolidation from 100 to 150 kPa ends balanced within 0.5 %;
//   - drained shear holds the lateral stresses within 1 % RMS (ASTM D4767)
//     with the PID servo while the axial strain reaches its target exactly;
//   - the ticked runner is deterministic and control ticks of n steps give
//     the same result as the rig's (n steps per tick, servo from the next tick);
//   - bad protocol keys name the field.
#include <gtest/gtest.h>

#include <cmath>

#include "virtual_triaxial/io/sample_file.h"
#include "virtual_triaxial/io/scene_error.h"
#include "virtual_triaxial/io/scene_parser.h"
#include "virtual_triaxial/protocol/stage_monitor.h"
#include "virtual_triaxial/protocol/stage_runner.h"

using namespace vt;
using protocol::StageType;

namespace {

const char* kSample = VT_SOURCE_DIR "/tests/data/sample_200_100kPa.h5";

struct Recorder : protocol::RunObserver {
  std::vector<dem::Measures> samples;
  std::vector<std::string> stages;
  void on_sample(const protocol::StageSpec& st, const dem::Measures& m) override {
    samples.push_back(m);
    stages.push_back(st.name);
  }
};

protocol::RunOptions options(std::int64_t interval, const std::string& strategy, double ki) {
  protocol::RunOptions o;
  o.control_interval = interval;
  o.sample_interval = 20 * interval;
  o.progress_seconds = 0;
  o.servo.strategy = strategy;
  o.servo.parameters.gain = 1.0;
  o.servo.parameters.ki = ki;
  o.servo.max_dimensionless_rate = 1e-4;
  return o;
}

protocol::StageSpec drained(double confining, double eps) {
  protocol::StageSpec s;
  s.name = "shear";
  s.type = StageType::DrainedShear;
  s.confining_pressure = confining;
  s.strain_rate_dimensionless = 1e-5;
  s.stop.axial_strain = eps;
  return s;
}

std::string parse_error(const std::string& yaml) {
  try {
    (void)io::parse_scene(yaml);
  } catch (const io::SceneError& e) {
    return e.what();
  }
  return "(accepted)";
}

}  // namespace

TEST(StageBoundary, AxesAndRatesPerStageType) {
  protocol::StageSpec s = drained(1e5, 0.1);
  s.axial_axis = 0;
  const double t0 = 2e-7, r = 1e-5 / t0;
  protocol::StageBoundary b = protocol::stage_boundary(s, t0);
  EXPECT_FALSE(b.servo[0]);
  EXPECT_TRUE(b.servo[1] && b.servo[2]);
  EXPECT_EQ(b.open_rate[0], r);
  EXPECT_EQ(b.target[1], 1e5);
  s.type = StageType::UndrainedShear;
  b = protocol::stage_boundary(s, t0);
  EXPECT_FALSE(b.any_servo());
  EXPECT_EQ(b.open_rate[0] + b.open_rate[1] + b.open_rate[2], 0.0) << "log rates sum to zero: constant volume";
  s.type = StageType::IsotropicConsolidation;
  b = protocol::stage_boundary(s, t0);
  EXPECT_EQ(b.servo_axes(), (std::vector<int>{0, 1, 2}));
}

TEST(StageMonitor, SofteningBalancedAndSampleOnlyCriteria) {
  protocol::StageSpec s = drained(1e5, 0.5);
  s.stop.softening = 0.2;
  protocol::StageMonitor m(s, protocol::stage_boundary(s, 1.0));
  protocol::TickSample t;
  t.stress[0] = t.stress[1] = 1e5;
  for (double q : {1e5, 2e5, 1.7e5, 1.61e5}) {
    t.q = q;
    EXPECT_EQ(m.check(t), "") << q;
  }
  t.q = 1.6e5;  // exactly (1 - 0.2) x peak
  EXPECT_NE(m.check(t).find("softening"), std::string::npos);

  protocol::StageSpec c;
  c.type = StageType::IsotropicConsolidation;
  c.confining_pressure = 1e5;
  c.stop.balanced = protocol::BalanceCriterion{0.005, 0.01};
  protocol::StageMonitor mc(c, protocol::stage_boundary(c, 1.0));
  protocol::TickSample u;
  u.stress[0] = u.stress[1] = 1e5;
  u.stress[2] = 1.004e5;
  EXPECT_EQ(mc.check(u), "") << "no UFR on a non-sample tick: not judged";
  u.ufr = 0.02;
  u.contacts = 100;
  EXPECT_EQ(mc.check(u), "") << "UFR above the limit";
  u.ufr = 0.005;
  EXPECT_NE(mc.check(u).find("balanced"), std::string::npos);
  u.stress[2] = 1.006e5;
  EXPECT_EQ(mc.check(u), "") << "z 0.6 % off the target";
  EXPECT_TRUE(protocol::is_sample_tick(10, 10, 200)) << "the first tick of a stage";
  EXPECT_FALSE(protocol::is_sample_tick(20, 10, 200));
  EXPECT_TRUE(protocol::is_sample_tick(400, 10, 200));
}

TEST(StageRunner, ServoConsolidationEndsBalancedAtTheNewPressure) {
  dem::Simulation sim(io::read_sample(kSample));
  sim.set_time_step_ratio(0.3);
  protocol::StageSpec c;
  c.name = "consolidation";
  c.type = StageType::IsotropicConsolidation;
  c.confining_pressure = 1.5e5;
  c.stop.balanced = protocol::BalanceCriterion{0.005, 0.05};
  c.stop.steps = 40000;
  protocol::StageRunner runner(sim, options(10, "pid", 0.3));
  Recorder rec;
  const protocol::RunReport r = runner.run({c}, rec);
  ASSERT_EQ(r.verdict, protocol::Verdict::Completed) << r.failure;
  ASSERT_NE(r.stages.at(0).stop_reason.find("balanced"), std::string::npos) << r.stages[0].stop_reason;
  const dem::Mat3 s = sim.current_stress();
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(s(i, i) / 1.5e5, 1.0, 0.005) << "axis " << i;
  EXPECT_EQ(r.steps % 10, 0) << "stages end on control ticks";
  EXPECT_EQ(r.ticks * 10, r.steps);
}

TEST(StageRunner, DrainedShearHoldsTheLateralStressAndReachesTheStrain) {
  dem::Simulation sim(io::read_sample(kSample));
  sim.set_time_step_ratio(0.3);
  protocol::StageRunner runner(sim, options(10, "pid", 0.6));
  Recorder rec;
  const protocol::RunReport r = runner.run({drained(1e5, 0.01)}, rec);
  ASSERT_EQ(r.verdict, protocol::Verdict::Completed) << r.failure;
  ASSERT_GT(rec.samples.size(), 10u);
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t k = 2; k < rec.samples.size(); ++k)  // the servo needs a few ticks to catch the drift
    for (int i = 0; i < 2; ++i) {
      const double e = rec.samples[k].stress(i, i) / 1e5 - 1.0;
      sum += e * e;
      ++n;
    }
  const double rms = std::sqrt(sum / static_cast<double>(n));
  EXPECT_LT(rms, 0.01) << "ASTM D4767: lateral stress within 1 % RMS";
  const dem::Measures& last = rec.samples.back();
  const double per_tick = 1e-5 * 0.3 * 10;  // eps' c_t steps: log strain per tick
  EXPECT_GE(last.strain[2], 0.01);
  EXPECT_LT(last.strain[2], 0.01 + per_tick * (1 + 1e-9));
  EXPECT_TRUE(r.shear.has_data);
  EXPECT_GT(r.shear.q_peak, 0.0) << "compression raises q";
  EXPECT_GT(r.shear.phi_peak, 0.0);
}

TEST(StageRunner, DrainedUnloadExtendsTheAxisUntilTheDeviatorFalls) {
  dem::Simulation sim(io::read_sample(kSample));
  sim.set_time_step_ratio(0.3);
  protocol::StageRunner runner(sim, options(10, "pid", 0.6));
  protocol::StageSpec unload = drained(1e5, 0.5);
  unload.name = "unload";
  unload.type = StageType::DrainedUnload;
  unload.stop.axial_strain.reset();
  unload.stop.deviator_below = 5e3;
  unload.stop.steps = 50000;
  Recorder rec;
  const protocol::RunReport r = runner.run({drained(1e5, 0.01), unload}, rec);
  ASSERT_EQ(r.verdict, protocol::Verdict::Completed) << r.failure;
  ASSERT_EQ(r.stages.size(), 2u);
  EXPECT_NE(r.stages[1].stop_reason.find("deviator"), std::string::npos) << r.stages[1].stop_reason;
  const dem::Measures& last = rec.samples.back();
  EXPECT_LE(last.q, 5e3);
  EXPECT_LT(last.strain[2], 0.0) << "the axial axis was extended (strains count from the stage start)";
  // The unloading is a fast transient (q falls by ~1e5 Pa within ~1000 steps),
  // so the servo trails by a little more than while shearing: 3 % here.
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(last.stress(i, i) / 1e5, 1.0, 0.03) << "lateral axis " << i;
}

TEST(StageRunner, TickedRunsAreDeterministicAndAbortEndsThem) {
  auto run = [](bool abort_early) {
    dem::Simulation sim(io::read_sample(kSample));
    protocol::StageRunner runner(sim, options(5, "proportional", 0.0));
    struct Stopper : Recorder {
      protocol::StageRunner* r = nullptr;
      bool stop = false;
      void on_sample(const protocol::StageSpec& st, const dem::Measures& m) override {
        Recorder::on_sample(st, m);
        if (stop && samples.size() == 3) r->abort();
      }
    } rec;
    rec.r = &runner;
    rec.stop = abort_early;
    const protocol::RunReport rep = runner.run({drained(1e5, 0.002)}, rec);
    return std::make_pair(rep, rec.samples);
  };
  const auto a = run(false), b = run(false);
  ASSERT_EQ(a.second.size(), b.second.size());
  for (std::size_t k = 0; k < a.second.size(); ++k)
    for (int i = 0; i < 3; ++i) ASSERT_EQ(a.second[k].stress(i, i), b.second[k].stress(i, i)) << k;
  const auto c = run(true);
  EXPECT_EQ(c.first.verdict, protocol::Verdict::Aborted);
  EXPECT_EQ(c.first.stages.at(0).stop_reason, "aborted");
  EXPECT_LT(c.first.steps, a.first.steps);
}

TEST(ProtocolKeys, BadValuesNameTheField) {
  const std::string parts = "particles:\n  distribution: {count: 10, radius_min: 1.0e-3, radius_max: 1.0e-3}\n";
  auto with = [&](const std::string& stages, const std::string& extra = "") { return parts + stages + extra; };
  EXPECT_NE(parse_error(with("stages:\n  - {type: drained_shear, strain_rate_dimensionless: 1.0e-5, "
                             "stop: {axial_strain: 0.1}}\n"))
                .find("stages[0].confining_pressure"),
            std::string::npos);
  EXPECT_NE(parse_error(with("stages:\n  - {type: relax, stop: {balanced: {ufr_below: 0.01}}}\n"))
                .find("stages[0].stop.balanced"),
            std::string::npos);
  EXPECT_NE(parse_error(with("stages:\n  - {type: undrained_shear, strain_rate_dimensionless: 1.0e-5, "
                             "stop: {softening: 1.5}}\n"))
                .find("stages[0].stop.softening"),
            std::string::npos);
  EXPECT_NE(parse_error(with("stages:\n  - {type: isotropic_consolidation, confining_pressure: 1.0e5, "
                             "strain_rate: 1.0, stop: {steps: 10}}\n"))
                .find("stages[0].strain_rate"),
            std::string::npos);
  const std::string relax = "stages:\n  - {type: relax, stop: {steps: 10}}\n";
  EXPECT_NE(parse_error(with(relax, "control: {interval: 3}\noutput: {interval: 100}\n")).find("output.interval"),
            std::string::npos);
  EXPECT_NE(parse_error(with(relax, "control: {servo: {strategy: bang_bang}}\n")).find("control.servo"),
            std::string::npos);
  EXPECT_NE(parse_error(with(relax, "control: {servo: {strategy: pid, ki: 3.0}}\n")).find("ki"), std::string::npos);
  const io::SceneConfig ok = io::parse_scene(
      with("stages:\n  - {type: drained_shear, confining_pressure: 1.0e5, strain_rate_dimensionless: 1.0e-5, "
           "axial_axis: x, stop: {axial_strain: 0.1, softening: 0.2}}\n",
           "control: {interval: 10, servo: {strategy: pid, gain: 0.8, ki: 0.4, max_rate_change: 1.0e-6}}\n"
           "output: {interval: 200}\n"));
  EXPECT_EQ(ok.stages[0].axial_axis, 0);
  EXPECT_EQ(*ok.stages[0].stop.softening, 0.2);
  const protocol::RunOptions o = ok.run_options();
  EXPECT_EQ(o.control_interval, 10);
  EXPECT_EQ(o.servo.strategy, "pid");
  EXPECT_EQ(o.servo.parameters.ki, 0.4);
  EXPECT_EQ(o.servo.max_dimensionless_rate_change, 1e-6);
}
