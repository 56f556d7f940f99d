// A stage judge's memory as numbers, and back. See stage_judge_state.h.
#include "virtual_triaxial/protocol/stage_judge_state.h"

#include <stdexcept>

#include "virtual_triaxial/protocol/stage_judge.h"

namespace vt::protocol {

namespace {

/// Every number of the state, by name: one list for both directions.
template <class S, class F>
void each_field(S& s, F&& f) {
  f("q_peak", s.q_peak);
  auto& m = s.shear.summary;
  f("shear.e0", m.e0);
  f("shear.phi_peak", m.phi_peak);
  f("shear.eps_peak", m.eps_peak);
  f("shear.q_peak", m.q_peak);
  f("shear.phi_end", m.phi_end);
  f("shear.eps_end", m.eps_end);
  f("shear.p_end", m.p_end);
  f("shear.q_end", m.q_end);
  f("shear.sum_imom", s.shear.sum_imom);
  f("shear.sum_weight", s.shear.sum_weight);
  f("shear.max_imom", s.shear.max_imom);
  f("shear.sum_imom_at_peak", s.shear.sum_imom_at_peak);
  f("shear.sum_weight_at_peak", s.shear.sum_weight_at_peak);
  f("shear.max_imom_at_peak", s.shear.max_imom_at_peak);
  f("rate0", s.rate0);
  f("rate", s.rate);
  f("rate_min", s.rate_min);
  f("rate_max", s.rate_max);
  f("interval_rate_sum", s.interval_rate_sum);
}

}  // namespace

std::map<std::string, double> to_fields(const StageJudgeState& s) {
  std::map<std::string, double> f;
  each_field(s, [&](const char* name, const double& v) { f[name] = v; });
  f["shear.has_data"] = s.shear.summary.has_data ? 1.0 : 0.0;
  f["shear.samples"] = static_cast<double>(s.shear.summary.samples);
  f["interval_ticks"] = static_cast<double>(s.interval_ticks);
  f["interval_constant"] = s.interval_constant ? 1.0 : 0.0;
  return f;
}

StageJudgeState from_fields(const std::map<std::string, double>& f, std::vector<double> rate_strategy) {
  auto get = [&](const std::string& name) {
    const auto it = f.find(name);
    if (it == f.end()) throw std::invalid_argument("judge." + name + ": missing");
    return it->second;
  };
  StageJudgeState s;
  each_field(s, [&](const char* name, double& v) { v = get(name); });
  s.shear.summary.has_data = get("shear.has_data") != 0.0;
  s.shear.summary.samples = static_cast<std::int64_t>(get("shear.samples"));
  s.interval_ticks = static_cast<std::int64_t>(get("interval_ticks"));
  s.interval_constant = get("interval_constant") != 0.0;
  s.rate_strategy = std::move(rate_strategy);
  return s;
}

ShearAccumulators ShearSummaryBuilder::accumulators() const {
  return {s_, sum_imom_, sum_weight_, max_imom_, sum_imom_at_peak_, sum_weight_at_peak_, max_imom_at_peak_};
}

void ShearSummaryBuilder::restore(const ShearAccumulators& a) {
  s_ = a.summary;
  sum_imom_ = a.sum_imom;
  sum_weight_ = a.sum_weight;
  max_imom_ = a.max_imom;
  sum_imom_at_peak_ = a.sum_imom_at_peak;
  sum_weight_at_peak_ = a.sum_weight_at_peak;
  max_imom_at_peak_ = a.max_imom_at_peak;
}

StageJudgeState StageJudge::save_state() const {
  StageJudgeState s;
  s.q_peak = monitor_.q_peak();
  s.shear = shear_.accumulators();
  s.rate0 = rate0_;
  s.rate = rate_;
  s.rate_min = rate_min_;
  s.rate_max = rate_max_;
  s.interval_rate_sum = interval_rate_sum_;
  s.interval_ticks = interval_ticks_;
  s.interval_constant = interval_constant_;
  if (strategy_) s.rate_strategy = strategy_->memory();
  return s;
}

void StageJudge::restore_state(const StageJudgeState& s) {
  if (strategy_) strategy_->restore_memory(s.rate_strategy);  // after the constructor's start()
  else if (!s.rate_strategy.empty())
    throw std::invalid_argument("judge.rate_strategy: this stage has no axial rate strategy, got " +
                                std::to_string(s.rate_strategy.size()) + " numbers");
  monitor_.restore_q_peak(s.q_peak);
  shear_.restore(s.shear);
  rate0_ = s.rate0;
  rate_ = s.rate;
  rate_min_ = s.rate_min;
  rate_max_ = s.rate_max;
  interval_rate_sum_ = s.interval_rate_sum;
  interval_ticks_ = s.interval_ticks;
  interval_constant_ = s.interval_constant;
}

}  // namespace vt::protocol
