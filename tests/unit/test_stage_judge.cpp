// The stage judge (protocol/stage_judge.h) that StageRunner and the rig's
// ProtocolSession share, fed synthetic ticks (no simulation):
//   - sample ticks: the stage's first tick and every multiple of the output
//     interval;
//   - order of the decisions: a stop request beats a met criterion, a met
//     criterion beats the step cap; the step cap ends the run with
//     `step_limit` and a message naming the stage and the cap; the cap is the
//     stage's `steps` criterion when it has one;
//   - the outcome, verdict and failure it writes into the report, also for a
//     failure reported from outside (unstable);
//   - the shear summary: the mean of I_mom up to the peak over strain, its
//     maximum, the strategy and the eps' range (= eps' of the stage for the
//     fixed strategy); at a fixed rate the mean is the plain mean bit for bit
//     (every weight exactly 1), with unequal weights the weighted closed form;
//   - the quasi-static verdict follows the mean against I_QS.
#include <gtest/gtest.h>

#include <cmath>

#include "virtual_triaxial/protocol/shear_summary.h"
#include "virtual_triaxial/protocol/stage_judge.h"

using namespace vt;
using protocol::StageType;
using protocol::TickDecision;

namespace {

constexpr double kT0 = 2e-7;  // [s]

protocol::RunOptions options(std::int64_t interval, std::int64_t sample_interval) {
  protocol::RunOptions o;
  o.control_interval = interval;
  o.sample_interval = sample_interval;
  o.quasi_static_threshold = 1e-3;
  return o;
}

protocol::StageSpec shear(double eps_rate, double eps_stop) {
  protocol::StageSpec s;
  s.name = "shear";
  s.type = StageType::DrainedShear;
  s.confining_pressure = 1e5;
  s.strain_rate_dimensionless = eps_rate;
  s.stop.axial_strain = eps_stop;
  return s;
}

protocol::TickSample tick(std::int64_t steps, double eps_a, double q = 1e4) {
  protocol::TickSample t;
  t.stage_steps = steps;
  t.eps_a = eps_a;
  t.p = 1e5 + q / 3;
  t.q = q;
  t.stress[0] = t.stress[1] = 1e5;
  t.stress[2] = 1e5 + q;
  return t;
}

dem::Measures sample(double eps_a, double phi, double i_mom) {
  dem::Measures m;
  m.strain = {0.0, 0.0, eps_a};
  m.phi = phi;
  m.moment_index = i_mom;
  m.void_ratio = 0.6;
  m.q = 1e4;
  m.p = 1e5;
  return m;
}

}  // namespace

TEST(StageJudge, SampleTicksAreTheFirstAndEveryOutputInterval) {
  protocol::StageJudge j(shear(1e-5, 0.1), options(10, 100), kT0);
  EXPECT_TRUE(j.is_sample_tick(10));
  for (std::int64_t k = 20; k < 100; k += 10) EXPECT_FALSE(j.is_sample_tick(k)) << k;
  EXPECT_TRUE(j.is_sample_tick(100));
  EXPECT_TRUE(j.is_sample_tick(300));
  EXPECT_FALSE(j.is_sample_tick(310));
}

TEST(StageJudge, AStopRequestBeatsACriterionWhichBeatsTheStepCap) {
  protocol::StageSpec st = shear(1e-5, 0.01);
  protocol::RunOptions o = options(10, 100);
  o.max_steps_per_stage = 50;
  {  // criterion met on the tick the cap is reached: the criterion ends the stage, the run goes on
    protocol::StageJudge j(st, o, kT0);
    const TickDecision d = j.decide(tick(50, 0.02), nullptr);
    EXPECT_EQ(d.kind, TickDecision::Kind::Criterion);
    EXPECT_NE(d.why.find("axial strain"), std::string::npos) << d.why;
    protocol::RunReport r;
    EXPECT_TRUE(j.finish(50, r));
    EXPECT_EQ(r.verdict, protocol::Verdict::Completed);
    EXPECT_EQ(r.stages.at(0).stop_reason, d.why);
    EXPECT_EQ(r.steps, 50);
  }
  {  // and a stop request beats both
    protocol::StageJudge j(st, o, kT0);
    const TickDecision d = j.decide(tick(50, 0.02), "preempted");
    EXPECT_EQ(d.kind, TickDecision::Kind::Stop);
    EXPECT_EQ(d.why, "preempted");
    protocol::RunReport r;
    EXPECT_FALSE(j.finish(50, r));
    EXPECT_EQ(r.verdict, protocol::Verdict::Preempted);
    EXPECT_EQ(r.failure, "preempted during stage 'shear'");
    EXPECT_EQ(r.stages.at(0).stop_reason, "preempted");
  }
  {  // no criterion: the cap ends the run
    protocol::StageJudge j(st, o, kT0);
    EXPECT_EQ(j.decide(tick(40, 0.001), nullptr).kind, TickDecision::Kind::Continue);
    const TickDecision d = j.decide(tick(50, 0.002), nullptr);
    EXPECT_EQ(d.kind, TickDecision::Kind::StepLimit);
    EXPECT_EQ(d.why, "step limit");
    protocol::RunReport r;
    EXPECT_FALSE(j.finish(50, r));
    EXPECT_EQ(r.verdict, protocol::Verdict::StepLimit);
    EXPECT_EQ(r.failure, "stage 'shear' reached the step limit 50 before any stop criterion");
    EXPECT_EQ(r.stages.at(0).stop_reason, "step limit");
  }
  {  // aborted
    protocol::StageJudge j(st, o, kT0);
    EXPECT_EQ(j.decide(tick(10, 0.0), "aborted").kind, TickDecision::Kind::Stop);
    protocol::RunReport r;
    EXPECT_FALSE(j.finish(10, r));
    EXPECT_EQ(r.verdict, protocol::Verdict::Aborted);
  }
}

TEST(StageJudge, TheStagesStepsCriterionIsItsCap) {
  protocol::StageSpec st;
  st.name = "relax";
  st.type = StageType::Relax;
  st.stop.steps = 30;
  protocol::StageJudge j(st, options(10, 100), kT0);
  EXPECT_EQ(j.step_cap(), 30);
  EXPECT_EQ(j.decide(tick(20, 0.0), nullptr).kind, TickDecision::Kind::Continue);
  const TickDecision d = j.decide(tick(30, 0.0), nullptr);
  EXPECT_EQ(d.kind, TickDecision::Kind::Criterion);  // the criterion, not the limit
  protocol::RunReport r;
  EXPECT_TRUE(j.finish(30, r));
  EXPECT_EQ(r.verdict, protocol::Verdict::Completed);
  EXPECT_FALSE(r.shear.has_data);  // not a shear stage
}

TEST(StageJudge, AFailureFromOutsideEndsTheRun) {
  protocol::StageJudge j(shear(1e-5, 0.1), options(10, 100), kT0);
  j.decide(tick(10, 0.0), nullptr);
  j.fail(protocol::Verdict::Unstable, "NaN in particle 3", "unstable: NaN in particle 3");
  protocol::RunReport r;
  r.steps = 100;  // an earlier stage
  EXPECT_FALSE(j.finish(20, r));
  EXPECT_EQ(r.verdict, protocol::Verdict::Unstable);
  EXPECT_EQ(r.failure, "NaN in particle 3");
  EXPECT_EQ(r.stages.at(0).stop_reason, "unstable: NaN in particle 3");
  EXPECT_EQ(r.stages.at(0).steps, 20);
  EXPECT_EQ(r.steps, 120);
}

TEST(StageJudge, FixedRateShearSummaryIsThePlainMeanToThePeak) {
  const double eps_rate = 1e-5;
  protocol::StageJudge j(shear(eps_rate, 0.1), options(10, 20), kT0);
  EXPECT_DOUBLE_EQ(j.first_axial_rate(), eps_rate / kT0);
  // phi rises to a peak on the 4th sample and falls; I_mom varies
  const double phi[] = {0.1, 0.2, 0.3, 0.5, 0.4, 0.35};
  const double imom[] = {3e-4, 1.1e-3, 7e-4, 9e-4, 5e-3, 2e-3};
  int recorded = 0;
  for (std::int64_t k = 10; recorded < 6; k += 10) {
    const TickDecision d = j.decide(tick(k, 1e-4 * static_cast<double>(k)), nullptr);
    EXPECT_EQ(d.kind, TickDecision::Kind::Continue);
    EXPECT_DOUBLE_EQ(d.axial_rate, eps_rate / kT0);  // fixed: the stage's rate on every tick
    if (!d.sample_tick) continue;
    EXPECT_EQ(d.sample_weight, 1.0);  // exactly
    j.record(sample(1e-4 * static_cast<double>(k), phi[recorded], imom[recorded]), d);
    ++recorded;
  }
  protocol::RunReport r;
  EXPECT_TRUE(j.finish(100, r));
  const protocol::ShearSummary& s = r.shear;
  ASSERT_TRUE(s.has_data);
  EXPECT_EQ(s.samples, 6);
  EXPECT_EQ(s.phi_peak, 0.5);
  const double plain = (((3e-4 + 1.1e-3) + 7e-4) + 9e-4) / 4.0;  // the samples up to the peak, in order
  EXPECT_EQ(s.mean_moment_index_to_peak, plain);                  // bit for bit
  EXPECT_EQ(s.max_moment_index_to_peak, 1.1e-3);                  // not the 5e-3 after the peak
  EXPECT_EQ(s.rate_strategy, "fixed");
  EXPECT_DOUBLE_EQ(s.strain_rate_min, eps_rate);
  EXPECT_DOUBLE_EQ(s.strain_rate_max, eps_rate);
  EXPECT_TRUE(s.quasi_static);  // 7.5e-4 < 1e-3 although one sample before the peak exceeds I_QS
}

TEST(ShearSummaryBuilder, TheMeanIsOverStrain) {
  // Closed forms: mean = sum(w_i I_i) / sum(w_i), w_i the strain each sample covers.
  // A fast stretch (1 unit of strain at I_mom 4e-3) then a slow one (3 units at 2e-4):
  // (4e-3 + 3 x 2e-4) / 4 = 1.15e-3.
  protocol::ShearSummaryBuilder b(2, 1e-3);
  b.add(sample(0.01, 0.2, 4e-3), 1.0);
  b.add(sample(0.04, 0.3, 2e-4), 3.0);
  protocol::ShearSummary s = b.summary();
  EXPECT_NEAR(s.mean_moment_index_to_peak, 1.15e-3, 1e-18);
  EXPECT_FALSE(s.quasi_static);
  EXPECT_EQ(s.max_moment_index_to_peak, 4e-3);
  // A slow start (3 units at 2e-4) and a short fast stretch (1 unit at 2e-3):
  // 6.5e-4, quasi-static, where the plain mean of the two samples (1.1e-3) is not.
  protocol::ShearSummaryBuilder c(2, 1e-3);
  c.add(sample(0.03, 0.2, 2e-4), 3.0);
  c.add(sample(0.04, 0.3, 2e-3), 1.0);
  s = c.summary();
  EXPECT_NEAR(s.mean_moment_index_to_peak, 6.5e-4, 1e-18);
  EXPECT_TRUE(s.quasi_static);
}

TEST(StageJudge, TheLastTickOfAStageCarriesASampleWeight) {
  // the stage ends between two sample ticks: its last tick is recorded too,
  // and a fixed rate still weighs it exactly 1
  protocol::StageJudge j(shear(1e-5, 0.0035), options(10, 100), kT0);
  for (std::int64_t k = 10; k < 40; k += 10) EXPECT_EQ(j.decide(tick(k, 1e-4 * k), nullptr).kind, TickDecision::Kind::Continue);
  const TickDecision d = j.decide(tick(40, 0.004), nullptr);
  EXPECT_TRUE(d.ends_stage());
  EXPECT_FALSE(d.sample_tick);
  EXPECT_EQ(d.sample_weight, 1.0);
}

TEST(StageJudge, BadOptionsNameTheField) {
  protocol::RunOptions o = options(10, 15);
  try {
    protocol::StageJudge j(shear(1e-5, 0.1), o, kT0);
    FAIL() << "accepted sample_interval 15 with control_interval 10";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sample_interval"), std::string::npos) << e.what();
  }
  try {
    protocol::StageJudge j(shear(1e-5, 0.1), options(10, 100), 0.0);
    FAIL() << "accepted t0 = 0";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("t0"), std::string::npos) << e.what();
  }
}
