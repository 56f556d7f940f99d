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
//   - the quasi-static verdict follows the mean against I_QS;
//   - the rate strategies: `predicted` starts (and stays) at eq. 84's
//     eps'_QS(target I_QS) / T0 for the specimen, against the closed form;
//     `adaptive` starts there too and then commands, tick for tick, what
//     control::AdaptiveRate commands fed the same I_mom; the summary names
//     the strategy and the eps' range that ran; a strategy without the
//     specimen it needs is refused naming `rate`.
#include <gtest/gtest.h>

#include <cmath>

#include "virtual_triaxial/protocol/shear_summary.h"
#include "virtual_triaxial/control/adaptive_rate.h"
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

namespace {

constexpr double kYoung = 7e10, kVoid = 0.62, kDelta = 1.3;  // specimen for eq. 84

protocol::StageSpec strategy_shear(control::RateStrategyKind kind, double target) {
  protocol::StageSpec s = shear(0.0, 0.1);
  s.strain_rate_dimensionless.reset();
  s.rate_spec.strategy = kind;
  s.rate_spec.adaptive.target = target;
  return s;
}

protocol::RunOptions strategy_options() {
  protocol::RunOptions o = options(10, 20);
  o.young_modulus = kYoung;
  o.qs_damping = quasi_static::QsDamping::OD;
  return o;
}

/// eq. 84 written out: eps'_QS = 0.27 e0^-4 (sigma_c/E)^0.67 Delta^-2.5 I (OD).
double eq84(double threshold) {
  return 0.27 * std::pow(kVoid, -4.0) * std::pow(1e5 / kYoung, 0.67) * std::pow(kDelta, -2.5) * threshold;
}

}  // namespace

TEST(StageJudge, PredictedRateIsEq84ForTheSpecimenAndIsHeld) {
  protocol::SpecimenAtStart sp{kVoid, kDelta};
  protocol::StageJudge j(strategy_shear(control::RateStrategyKind::Predicted, 1.0), strategy_options(), kT0, sp);
  const double expected = eq84(1e-3) / kT0;
  EXPECT_NEAR(j.first_axial_rate(), expected, 1e-12 * expected);
  EXPECT_STREQ(j.strategy_name(), "predicted");
  EXPECT_FALSE(j.needs_moment_index());
  for (std::int64_t k = 10; k <= 50; k += 10) {
    const TickDecision d = j.decide(tick(k, 1e-4 * static_cast<double>(k)), nullptr);
    EXPECT_EQ(d.axial_rate, j.first_axial_rate());
  }
  // target 0.5: eq. 84 is linear in I_QS
  protocol::StageJudge h(strategy_shear(control::RateStrategyKind::Predicted, 0.5), strategy_options(), kT0, sp);
  EXPECT_NEAR(h.first_axial_rate(), 0.5 * expected, 1e-12 * expected);
}

TEST(StageJudge, AdaptiveRateCommandsWhatTheLawCommandsAndTheSummaryShowsTheRange) {
  protocol::SpecimenAtStart sp{kVoid, kDelta};
  protocol::StageSpec st = strategy_shear(control::RateStrategyKind::Adaptive, 0.7);
  st.rate_spec.adaptive.smoothing_ticks = 2;
  st.rate_spec.adaptive.response_ticks = 3;
  st.rate_spec.adaptive.max_change = 0.1;
  protocol::StageJudge j(st, strategy_options(), kT0, sp);
  EXPECT_TRUE(j.needs_moment_index());
  const double rate0 = eq84(0.7e-3) / kT0;
  EXPECT_NEAR(j.first_axial_rate(), rate0, 1e-12 * rate0);
  control::AdaptiveRateParameters p = st.rate_spec.adaptive;
  p.t0 = kT0;
  control::AdaptiveRate law(p);
  law.start(j.first_axial_rate());
  // the index first sits far above the target (rate falls), then far below (rate rises)
  double lo = j.first_axial_rate(), hi = lo, eps = 0.0;
  protocol::TickSample t0s = tick(10, 0.0);
  EXPECT_THROW(protocol::StageJudge(st, strategy_options(), kT0, sp).decide(t0s, nullptr), std::logic_error)
      << "adaptive without the moment index";
  for (std::int64_t k = 10; k <= 400; k += 10) {
    protocol::TickSample t = tick(k, eps);
    t.moment_index = k <= 200 ? 5e-3 : 1e-4;
    const double ran = law.rate();
    const TickDecision d = j.decide(t, nullptr);
    const double want = law.update({*t.moment_index, 1e-3});
    ASSERT_EQ(d.axial_rate, want) << "tick " << k;  // bit for bit
    lo = std::min(lo, ran);
    hi = std::max(hi, ran);
    eps += ran * kT0 * 1e-3;
    if (d.sample_tick) j.record(sample(eps, 0.3, *t.moment_index), d);
  }
  EXPECT_LT(lo, 0.5 * j.first_axial_rate());
  protocol::RunReport r;
  j.finish(400, r);
  EXPECT_EQ(r.shear.rate_strategy, "adaptive");
  EXPECT_NEAR(r.shear.strain_rate_min, lo * kT0, 1e-15 * hi * kT0);
  EXPECT_NEAR(r.shear.strain_rate_max, hi * kT0, 1e-15 * hi * kT0);
}

TEST(StageJudge, AStrategyWithoutItsSpecimenIsRefusedNamingRate) {
  for (const auto kind : {control::RateStrategyKind::Predicted, control::RateStrategyKind::Adaptive}) {
    try {
      protocol::StageJudge j(strategy_shear(kind, 1.0), strategy_options(), kT0);
      FAIL() << "accepted " << control::to_string(kind) << " without a specimen";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind("rate", 0), 0u) << e.what();
    }
  }
}

