#include "virtual_triaxial/protocol/stage_runner.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace vt::protocol {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
const char* axis_name(int a) { return a == 0 ? "x" : (a == 1 ? "y" : "z"); }
}  // namespace

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::Completed: return "completed";
    case Verdict::Unstable: return "unstable";
    case Verdict::StepLimit: return "step_limit";
  }
  return "?";
}

void StageRunner::apply_rates(const StageSpec& st) {
  const double t0 = sim_.time_scale().t0, dt = sim_.dt();
  const double rate = st.strain_rate ? *st.strain_rate
                                     : (st.strain_rate_dimensionless ? *st.strain_rate_dimensionless / t0 : 0.0);
  dem::Vec3 r{};
  switch (st.type) {
    case StageType::IsotropicCompression:
      r = {-rate, -rate, -rate};
      break;
    case StageType::UndrainedShear: {
      const double lateral = (1.0 / std::sqrt(1.0 - rate * dt) - 1.0) / dt;
      r = {lateral, lateral, lateral};
      r[st.axial_axis] = -rate;
      break;
    }
    case StageType::Relax:
      break;
  }
  sim_.set_strain_rates(r);
}

std::string StageRunner::stop_reason(const StageSpec& st, std::int64_t k, const dem::Measures* sample) const {
  const StopCriteria& c = st.stop;
  std::ostringstream s;
  if (c.steps && k >= *c.steps) {
    s << "steps " << k;
    return s.str();
  }
  if (c.mean_stress) {
    const double p = sim_.current_mean_stress();
    if (p >= *c.mean_stress) {
      s << "mean stress " << p << " Pa >= " << *c.mean_stress << " Pa";
      return s.str();
    }
  }
  if (c.axial_strain) {
    const double eps = -std::log(sim_.cell().h()(st.axial_axis, st.axial_axis) / axial_start_);
    if (eps >= *c.axial_strain) {
      s << "axial strain " << eps << " >= " << *c.axial_strain;
      return s.str();
    }
  }
  if (c.ufr_below && sample && sample->ufr < *c.ufr_below && sample->contacts > 0) {
    s << "UFR " << sample->ufr << " < " << *c.ufr_below;
    return s.str();
  }
  return {};
}

std::string StageRunner::progress_line(const StageSpec& st, std::int64_t k, const dem::Measures& m,
                                       double rate) const {
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "[%s] step %lld  eps_%s %.3f%%  eps_v %.3f%%  p %.1f kPa  q %.1f kPa  e %.4f  Z %.2f  "
                "I_mom %.2e  UFR %.2e  KE %.2e J  (%.0f steps/s)",
                st.name.c_str(), static_cast<long long>(k), axis_name(st.axial_axis), 100 * m.strain[st.axial_axis],
                100 * m.volumetric_strain, m.p / 1e3, m.q / 1e3, m.void_ratio, m.coordination_number,
                m.moment_index, m.ufr, m.energy.kinetic(), rate);
  return buf;
}

bool StageRunner::run_stage(const StageSpec& st, RunObserver& obs, RunReport& report) {
  sim_.reset_strain_reference();
  axial_start_ = sim_.cell().h()(st.axial_axis, st.axial_axis);
  apply_rates(st);
  obs.on_stage_start(st, sim_);
  ShearSummaryBuilder shear(st.axial_axis, options_.quasi_static_threshold);
  StageOutcome out;
  out.name = st.name;
  out.type = st.type;
  const auto t_start = Clock::now();
  auto t_progress = t_start;
  std::int64_t k = 0, k_progress = 0;
  const std::int64_t cap = st.stop.steps ? *st.stop.steps : options_.max_steps_per_stage;
  bool ok = true;
  dem::Measures last{};
  auto mark_unstable = [&]() {
    report.verdict = Verdict::Unstable;
    report.failure = sim_.failure();
    out.stop_reason = "unstable: " + sim_.failure();
    return false;
  };
  auto record = [&]() {
    last = sim_.measures();
    obs.on_sample(st, last);
    if (st.type == StageType::UndrainedShear) shear.add(last);
    if (options_.keep_last_good) report.last_good = sim_.state();
  };
  while (true) {
    const bool sample = k % options_.sample_interval == 0;
    if (!sim_.step(sample)) {
      ok = mark_unstable();
      break;
    }
    ++k;
    if (sample) record();
    std::string why = stop_reason(st, k, sample ? &last : nullptr);
    if (!why.empty()) {
      if (!sample) {  // one more step so that the stage ends on a sample
        if (!sim_.step(true)) {
          ok = mark_unstable();
          break;
        }
        ++k;
        record();
      }
      out.stop_reason = why;
      break;
    }
    if (k >= cap) {
      ok = false;
      report.verdict = Verdict::StepLimit;
      report.failure = "stage '" + st.name + "' reached the step limit " + std::to_string(cap) +
                       " before any stop criterion";
      out.stop_reason = "step limit";
      break;
    }
    if (options_.progress_seconds > 0 && seconds_since(t_progress) >= options_.progress_seconds &&
        last.step > 0) {
      const double rate = static_cast<double>(k - k_progress) / seconds_since(t_progress);
      obs.on_progress(progress_line(st, k, last, rate));
      t_progress = Clock::now();
      k_progress = k;
    }
  }
  out.steps = k;
  report.steps += k;
  report.stages.push_back(out);
  if (st.type == StageType::UndrainedShear) report.shear = shear.summary();
  if (last.step > 0 || k > 0) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "[%s] done after %lld steps (%.1f s): %s", st.name.c_str(),
                  static_cast<long long>(k), seconds_since(t_start), out.stop_reason.c_str());
    obs.on_progress(buf);
  }
  obs.on_stage_end(out);
  sim_.set_strain_rates({});
  return ok;
}

RunReport StageRunner::run(const std::vector<StageSpec>& stages, RunObserver& observer) {
  RunReport report;
  const auto t0 = Clock::now();
  for (const StageSpec& st : stages)
    if (!run_stage(st, observer, report)) break;
  report.wall_seconds = seconds_since(t0);
  return report;
}

}  // namespace vt::protocol
