#include "virtual_triaxial/protocol/stage_judge.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vt::protocol {

StageJudge::StageJudge(const StageSpec& stage, const RunOptions& options, double t0)
    : stage_(stage),
      boundary_(stage_boundary(stage, t0)),
      monitor_(stage, boundary_),
      shear_(stage.axial_axis, options.quasi_static_threshold),
      control_interval_(options.control_interval),
      sample_interval_(options.sample_interval),
      cap_(stage.stop.steps ? *stage.stop.steps : options.max_steps_per_stage),
      t0_(t0) {
  const std::string bad = validate(options);
  if (!bad.empty()) throw std::invalid_argument("RunOptions: " + bad);
  if (!(std::isfinite(t0) && t0 > 0)) throw std::invalid_argument("t0: must be finite and > 0");
  out_.name = stage.name;
  out_.type = stage.type;
  rate0_ = rate_ = boundary_.servo[stage.axial_axis] ? 0.0 : boundary_.open_rate[stage.axial_axis];
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
  // The strain this tick covered, for the weight of the next recorded sample.
  interval_rate_sum_ += rate_;
  ++interval_ticks_;
  if (rate_ != rate0_) interval_constant_ = false;
  if (d.sample_tick || d.ends_stage()) {
    d.sample_weight = interval_constant_ || rate0_ == 0.0
                          ? 1.0
                          : interval_rate_sum_ / (static_cast<double>(interval_ticks_) * rate0_);
    interval_rate_sum_ = 0.0;
    interval_ticks_ = 0;
    interval_constant_ = true;
  }
  // Rate strategy `fixed`: the stage's own rate on every tick.
  d.axial_rate = rate_;
  rate_min_ = std::min(rate_min_, std::abs(rate_));
  rate_max_ = std::max(rate_max_, std::abs(rate_));
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
    report.shear.rate_strategy = "fixed";
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
