// The stage runner: undrained shear keeps the cell volume constant to
// round-off, stop criteria end stages where they say, samples are recorded,
// and the shear summary finds the peak.
#include <gtest/gtest.h>

#include <cmath>

#include "virtual_triaxial/dem/cloud_generator.h"
#include "virtual_triaxial/protocol/sample_preparation.h"
#include "virtual_triaxial/protocol/stage_runner.h"

using namespace vt;

namespace {

const dem::SimulationState& prepared() {
  static const dem::SimulationState st = [] {
    protocol::PreparationSettings s;
    s.radii = dem::table_radii(160, {{0.8e-3, 0.25}, {0.933e-3, 0.25}, {1.067e-3, 0.25}, {1.2e-3, 0.25}});
    s.mu1 = 0.1;
    s.seed = 2;
    const protocol::PreparationResult r = protocol::prepare_sample(s);
    EXPECT_TRUE(r.converged) << r.failure;
    return r.state;
  }();
  return st;
}

struct Recorder : protocol::RunObserver {
  std::vector<dem::Measures> samples;
  std::vector<double> volumes;
  void on_sample(const protocol::StageSpec&, const dem::Measures& m) override {
    samples.push_back(m);
    volumes.push_back(m.volume);
  }
};

protocol::StageSpec stage(protocol::StageType t, double eps_prime) {
  protocol::StageSpec s;
  s.name = protocol::to_string(t);
  s.type = t;
  if (t != protocol::StageType::Relax) s.strain_rate_dimensionless = eps_prime;
  return s;
}

}  // namespace

TEST(StageRunner, UndrainedShearKeepsTheVolumeConstantAndStopsAtTheStrain) {
  dem::Simulation sim(prepared());
  sim.set_time_step_ratio(0.3);
  protocol::RunOptions opt;
  opt.sample_interval = 50;
  opt.progress_seconds = 0;
  protocol::StageRunner runner(sim, opt);
  protocol::StageSpec shear = stage(protocol::StageType::UndrainedShear, 1e-4);
  shear.stop.axial_strain = 0.02;
  Recorder rec;
  const double v0 = sim.cell().volume();
  const protocol::RunReport r = runner.run({shear}, rec);
  ASSERT_EQ(r.verdict, protocol::Verdict::Completed) << r.failure;
  ASSERT_GT(rec.samples.size(), 10u);
  for (double v : rec.volumes) EXPECT_NEAR(v / v0, 1.0, 1e-9);
  EXPECT_NEAR(sim.cell().volume() / v0, 1.0, 1e-9);
  const dem::Measures& last = rec.samples.back();
  EXPECT_GE(last.strain.z, 0.02);
  EXPECT_LT(last.strain.z, 0.02 + 2 * 1e-4 * 0.3 + 1e-9) << "stops within a step of the criterion";
  EXPECT_NEAR(last.strain.x, -0.5 * last.strain.z, 1e-9) << "lateral strains -eps_a/2";
  EXPECT_NEAR(last.volumetric_strain, 0.0, 1e-9);
  // Summary: the peak is the largest phi seen, at its strain.
  double best = 0, eps_best = 0;
  for (const dem::Measures& m : rec.samples)
    if (m.phi > best) best = m.phi, eps_best = m.strain.z;
  EXPECT_DOUBLE_EQ(r.shear.phi_peak, best);
  EXPECT_DOUBLE_EQ(r.shear.eps_peak, eps_best);
  EXPECT_GT(r.shear.q_peak, 0.0);
}

TEST(StageRunner, CompressionStopsAtTheMeanStressAndRelaxStopsOnSteps) {
  dem::Simulation sim(prepared());
  protocol::RunOptions opt;
  opt.sample_interval = 20;
  opt.progress_seconds = 0;
  protocol::StageRunner runner(sim, opt);
  protocol::StageSpec comp = stage(protocol::StageType::IsotropicCompression, 1e-5);
  comp.stop.mean_stress = 150e3;
  protocol::StageSpec relax = stage(protocol::StageType::Relax, 0);
  relax.stop.steps = 300;
  Recorder rec;
  const protocol::RunReport r = runner.run({comp, relax}, rec);
  ASSERT_EQ(r.verdict, protocol::Verdict::Completed) << r.failure;
  ASSERT_EQ(r.stages.size(), 2u);
  EXPECT_NE(r.stages[0].stop_reason.find("mean stress"), std::string::npos) << r.stages[0].stop_reason;
  EXPECT_GE(r.stages[1].steps, 300);
  EXPECT_LE(r.stages[1].steps, 301);
  EXPECT_EQ(sim.strain_rates().x, 0.0) << "rates cleared after the run";
}

TEST(StageRunner, StepLimitAndInstabilityEndTheRunWithTheirVerdicts) {
  {
    dem::Simulation sim(prepared());
    protocol::RunOptions opt;
    opt.progress_seconds = 0;
    opt.max_steps_per_stage = 100;
    protocol::StageRunner runner(sim, opt);
    protocol::StageSpec comp = stage(protocol::StageType::IsotropicCompression, 1e-7);
    comp.stop.mean_stress = 1e9;
    Recorder rec;
    const protocol::RunReport r = runner.run({comp}, rec);
    EXPECT_EQ(r.verdict, protocol::Verdict::StepLimit);
    EXPECT_NE(r.failure.find("step limit"), std::string::npos);
  }
  {
    dem::Simulation sim(prepared());
    protocol::RunOptions opt;
    opt.progress_seconds = 0;
    protocol::StageRunner runner(sim, opt);
    protocol::StageSpec crush = stage(protocol::StageType::IsotropicCompression, 0.05);
    crush.stop.steps = 5000;
    Recorder rec;
    const protocol::RunReport r = runner.run({crush}, rec);
    EXPECT_EQ(r.verdict, protocol::Verdict::Unstable);
    EXPECT_FALSE(r.failure.empty());
    ASSERT_TRUE(r.last_good.has_value());
  }
}
