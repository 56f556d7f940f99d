#include "virtual_triaxial/protocol/stage_judge.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "virtual_triaxial/quasi_static/dispersity_index.h"
#include "virtual_triaxial/quasi_static/qs_rate_prediction.h"

namespace vt::protocol {

namespace {

/// The first rate of `predicted` and `adaptive` [1/s]: eq. 84 at target x I_QS
/// for the specimen at the stage start, over T0 (eq. 85). Eq. 84 has an OD and
/// an ND exponent of Delta; the other damping models use OD's (-2.5, the more
/// conservative for Delta > 1).
double predicted_rate(const StageSpec& st, const RunOptions& o, double t0, const SpecimenAtStart& sp) {
  const std::string field = "rate (stage '" + st.name + "', strategy " + control::to_string(st.rate_spec.strategy) + ")";
  if (!(sp.void_ratio > 0.0 && sp.dispersity_index >= 1.0 && o.young_modulus > 0.0))
    throw std::invalid_argument(field + ": needs the specimen's void ratio, dispersity index and Young's modulus "
                                        "for the eq. 84 prediction");
  const double sigma_c = st.confining_pressure.value_or(0.0);
  if (!(sigma_c > 0.0))
    throw std::invalid_argument(field + ": needs the stage's confining_pressure (sigma_c of eq. 84)");
  const quasi_static::QsSample sample{sp.void_ratio, sigma_c / o.young_modulus, sp.dispersity_index};
  const double threshold = st.rate_spec.adaptive.target * o.quasi_static_threshold;
  return quasi_static::dimensional_rate(quasi_static::predict_qs_rate(sample, o.qs_damping, threshold).eps_prime_qs,
                                        t0);
}

}  // namespace

SpecimenAtStart specimen_at_start(const dem::Simulation& sim) {
  SpecimenAtStart s;
  s.void_ratio = sim.cell().volume() / sim.particles().solid_volume() - 1.0;
  s.dispersity_index = quasi_static::dispersity_index(sim.particles().radius);
  return s;
}

StageJudge::StageJudge(const StageSpec& stage, const RunOptions& options, double t0, const SpecimenAtStart& specimen)
    : stage_(stage),
      boundary_(stage_boundary(stage, t0)),
      monitor_(stage, boundary_),
      shear_(stage.axial_axis, options.quasi_static_threshold),
      control_interval_(options.control_interval),
      sample_interval_(options.sample_interval),
      cap_(stage.stop.steps ? *stage.stop.steps : options.max_steps_per_stage),
      t0_(t0),
      quasi_static_threshold_(options.quasi_static_threshold) {
  const std::string bad = validate(options);
  if (!bad.empty()) throw std::invalid_argument("RunOptions: " + bad);
  if (!(std::isfinite(t0) && t0 > 0)) throw std::invalid_argument("t0: must be finite and > 0");
  out_.name = stage.name;
  out_.type = stage.type;
  rate0_ = boundary_.servo[stage.axial_axis] ? 0.0 : boundary_.open_rate[stage.axial_axis];
  if (stage.rate_spec.strategy != control::RateStrategyKind::Fixed) rate0_ = predicted_rate(stage, options, t0, specimen);
  if (rate0_ > 0.0) {  // an open-loop axial rate: the strategy commands it
    strategy_ = control::make_rate_strategy(stage.rate_spec, t0);
    needs_index_ = stage.rate_spec.strategy == control::RateStrategyKind::Adaptive;
    strategy_->start(rate0_);
    rate0_ = strategy_->rate();  // adaptive: clamped to [eps'_min, eps'_max] / T0
  }
  rate_ = rate0_;
  rate_min_ = rate_max_ = std::abs(rate0_);
}

bool StageJudge::is_sample_tick(std::int64_t stage_steps) const {
  return protocol::is_sample_tick(stage_steps, control_interval_, sample_interval_);
}

TickDecision StageJudge::decide(const TickSample& s, const char* stop_request) {
  TickDecision d;
  d.sample = s;
  d.sample_tick = is_sample_tick(s.stage_steps);
  d.why = monitor_.check(s);
  if (!d.why.empty()) d.kind = TickDecision::Kind::Criterion;
  if (stop_request) {
    d.kind = TickDecision::Kind::Stop;
    d.why = stop_request;
  } else if (d.why.empty() && s.stage_steps >= cap_) {
    d.kind = TickDecision::Kind::StepLimit;
    d.why = "step limit";
  }
  switch (d.kind) {
    case TickDecision::Kind::Continue: break;
    case TickDecision::Kind::Criterion: out_.stop_reason = d.why; break;
    case TickDecision::Kind::StepLimit:
      fail(Verdict::StepLimit,
           "stage '" + stage_.name + "' reached the step limit " + std::to_string(cap_) + " before any stop criterion",
           d.why);
      break;
    case TickDecision::Kind::Stop:
      fail(d.why == "preempted" ? Verdict::Preempted : Verdict::Aborted, d.why + " during stage '" + stage_.name + "'",
           d.why);
      break;
  }
  // The strain this tick covered, for the weight of the next recorded sample:
  // at the rate it ran at (the rig's applied rate when an external node commands it).
  const double ran = s.applied_axial_rate ? *s.applied_axial_rate : rate_;
  interval_rate_sum_ += ran;
  ++interval_ticks_;
  if (ran != rate0_) interval_constant_ = false;
  rate_min_ = std::min(rate_min_, std::abs(ran));
  rate_max_ = std::max(rate_max_, std::abs(ran));
  if (d.sample_tick || d.ends_stage()) {
    d.sample_weight = interval_constant_ || rate0_ == 0.0
                          ? 1.0
                          : interval_rate_sum_ / (static_cast<double>(interval_ticks_) * rate0_);
    interval_rate_sum_ = 0.0;
    interval_ticks_ = 0;
    interval_constant_ = true;
  }
  // The rate strategy: the axial rate of the next tick.
  if (strategy_ && !d.ends_stage()) {
    control::RateInput in;
    in.quasi_static_threshold = quasi_static_threshold_;
    if (needs_moment_index()) {
      if (!s.moment_index)
        throw std::logic_error("StageJudge::decide: the adaptive rate needs the moment index on every tick");
      in.moment_index = *s.moment_index;
    }
    rate_ = strategy_->update(in);
  }
  d.axial_rate = rate_;
  return d;
}

void StageJudge::record(const dem::Measures& m, const TickDecision& d) {
  if (is_shear(stage_.type)) shear_.add(m, d.sample_weight);
}

void StageJudge::fail(Verdict verdict, const std::string& failure, const std::string& stop_reason) {
  verdict_ = verdict;
  failure_ = failure;
  out_.stop_reason = stop_reason;
}

bool StageJudge::finish(std::int64_t steps, RunReport& report) {
  out_.steps = steps;
  report.steps += steps;
  report.stages.push_back(out_);
  if (is_shear(stage_.type)) {
    report.shear = shear_.summary();
    report.shear.rate_strategy = strategy_name();
    report.shear.strain_rate_min = rate_min_ * t0_;
    report.shear.strain_rate_max = rate_max_ * t0_;
  }
  if (verdict_ != Verdict::Completed) {
    report.verdict = verdict_;
    report.failure = failure_;
    return false;
  }
  return true;
}

}  // namespace vt::protocol
