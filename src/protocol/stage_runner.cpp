#include "virtual_triaxial/protocol/stage_runner.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "virtual_triaxial/dem/axis_stiffness.h"
#include "virtual_triaxial/protocol/run_checkpoint.h"
#include "virtual_triaxial/protocol/stage_judge.h"

namespace vt::protocol {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
const char* axis_name(int a) { return a == 0 ? "x" : (a == 1 ? "y" : "z"); }

/// Velocity gradient (extension positive) that scales L_i by exp(-r_i dt) per step.
dem::Vec3 velocity_gradient(const double rates[3], double dt) {
  dem::Vec3 l;
  for (int i = 0; i < 3; ++i) l[i] = std::expm1(-rates[i] * dt) / dt;
  return l;
}
}  // namespace

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::Completed: return "completed";
    case Verdict::Unstable: return "unstable";
    case Verdict::StepLimit: return "step_limit";
    case Verdict::Aborted: return "aborted";
    case Verdict::Preempted: return "preempted";
  }
  return "?";
}

std::string validate(const RunOptions& o) {
  if (o.control_interval < 1) return "control_interval: must be an integer >= 1";
  if (o.sample_interval < 1) return "sample_interval: must be an integer >= 1";
  if (o.sample_interval % o.control_interval != 0)
    return "sample_interval: must be a multiple of control_interval (" + std::to_string(o.control_interval) +
           ") so that samples fall on control ticks";
  if (!(std::isfinite(o.servo.max_dimensionless_rate) && o.servo.max_dimensionless_rate > 0))
    return "servo.max_dimensionless_rate: must be finite and > 0";
  if (!(o.quasi_static_threshold > 0)) return "quasi_static_threshold: must be > 0";
  if (o.checkpoint_ticks < 0) return "checkpoint_ticks: must be >= 0";
  if (!(std::isfinite(o.checkpoint_seconds) && o.checkpoint_seconds >= 0)) return "checkpoint_seconds: must be >= 0";
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

bool StageRunner::run_stage(const StageSpec& st, std::size_t index, RunObserver& obs, RunReport& report,
                            const RunCheckpoint* resume) {
  if (!resume) sim_.reset_strain_reference();  // a resumed stage keeps its reference (in the state)
  const double t0 = sim_.time_scale().t0;
  const std::int64_t n = options_.control_interval;
  RunOptions options = options_;
  options.young_modulus = sim_.settings().material.young;
  // a resumed stage: the specimen as it was at the stage start (the rate strategies' eq. 84)
  const SpecimenAtStart specimen = resume ? resume->specimen : specimen_at_start(sim_);
  StageJudge judge(st, options, t0, specimen);
  const StageBoundary& boundary = judge.boundary();
  std::unique_ptr<control::ServoStrategy> servo;
  double servo_start = 0.0;
  double rates[3];
  for (int i = 0; i < 3; ++i) rates[i] = boundary.open_rate[i];
  rates[st.axial_axis] = boundary.servo[st.axial_axis] ? 0.0 : judge.first_axial_rate();
  if (boundary.any_servo()) {
    control::ServoParameters p = options_.servo.parameters;
    p.max_strain_rate = options_.servo.max_dimensionless_rate / t0;
    p.max_rate_change = options_.servo.max_dimensionless_rate_change / t0;
    servo = control::make_servo(options_.servo.strategy, p);
    servo->init({boundary.target[0], boundary.target[1], boundary.target[2]},
                {boundary.servo[0], boundary.servo[1], boundary.servo[2]});
    servo_start = resume ? resume->servo_start_time : sim_.time();
    servo->start(servo_start);
    if (resume) servo->restore_memory(resume->servo_memory);
    for (int i = 0; i < 3; ++i)
      if (boundary.servo[i]) rates[i] = 0.0;
  }
  std::int64_t k = 0, k_progress = 0;
  if (resume) {
    judge.restore_state(resume->judge);
    for (int i = 0; i < 3; ++i) rates[i] = resume->rates[i];
    k = k_progress = resume->stage_steps;
    obs.on_progress("[" + st.name + "] resumed from the checkpoint at stage step " + std::to_string(k));
  } else {
    obs.on_stage_start(st, sim_);
    if (st.rate_spec.strategy != control::RateStrategyKind::Fixed) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "[%s] rate strategy %s: first eps' = %.3g (eq. 84 at %.2g I_QS)", st.name.c_str(),
                    judge.strategy_name(), judge.first_axial_rate() * t0, st.rate_spec.adaptive.target);
      obs.on_progress(buf);
    }
  }
  const auto t_start = Clock::now();
  auto t_progress = t_start;
  dem::Measures last{};
  auto unstable = [&]() {
    judge.fail(Verdict::Unstable, sim_.failure(), "unstable: " + sim_.failure());
  };
  auto record = [&](const TickDecision& d, bool measured) {
    if (!measured) last = sim_.measures();
    obs.on_sample(st, last);
    judge.record(last, d);
    if (options_.keep_last_good) keep_last_good(report);
  };
  while (true) {
    const double dt = sim_.dt();  // per tick: the contacts basis refreshes it (dem/contact_time_step.h)
    sim_.set_strain_rates(velocity_gradient(rates, dt));
    const bool sample = judge.is_sample_tick(k + n);
    const bool measure_end = sample || servo || n > 1 || judge.needs_moment_index();
    bool stepped = true;
    for (std::int64_t s = 0; s < n && stepped; ++s) stepped = sim_.step(measure_end && s == n - 1);
    if (!stepped) {
      unstable();
      k += n;  // partial tick counted as whole: the run ends here anyway
      break;
    }
    k += n;
    ++report.ticks;
    checkpoints_.tick();
    const dem::Mat3 stress = sim_.current_stress();
    if (servo) {
      control::ServoInput in;
      in.time = sim_.time();
      // the time the next tick's rate will act (the contacts basis may have refreshed dt; as dem_node's control_period)
      in.dt = sim_.dt() * static_cast<double>(n);
      in.stress = {stress(0, 0), stress(1, 1), stress(2, 2)};
      in.stiffness = dem::axis_stiffness(sim_);
      const control::ServoOutput o = servo->update(in);
      for (int i = 0; i < 3; ++i)
        if (boundary.servo[i]) rates[i] = o.strain_rate[i];
    }
    TickSample ts;
    ts.stage_steps = k;
    ts.eps_a = -sim_.cell().log_strain()[st.axial_axis];
    ts.p = stress.trace() / 3.0;
    ts.q = stress(2, 2) - std::min(stress(0, 0), stress(1, 1));
    for (int i = 0; i < 3; ++i) ts.stress[i] = stress(i, i);
    if (sample || judge.needs_moment_index()) {  // of the tick's measured last step
      const dem::Measures now = sim_.measures();
      ts.moment_index = now.moment_index;
      if (sample) {
        last = now;
        ts.ufr = last.ufr;
        ts.contacts = last.contacts;
      }
    }
    const TickDecision d = judge.decide(ts, abort_ ? "aborted" : nullptr);
    if (sample) record(d, true);
    if (d.ends_stage()) {
      if (!sample && d.kind != TickDecision::Kind::Stop) {
        if (!measure_end && !sim_.step(true)) {  // one more measured step so that the stage ends on a sample
          unstable();
          break;
        }
        if (!measure_end) ++k;
        record(d, false);
      }
      break;
    }
    if (!boundary.servo[st.axial_axis]) rates[st.axial_axis] = d.axial_rate;
    if (sample && checkpoints_.due()) {  // everything the next tick depends on
      RunCheckpoint c = checkpoint_of(index, k, rates, report, wall_before_ + seconds_since(run_start_), judge,
                                      specimen, servo != nullptr);
      if (servo) c.servo_memory = servo->memory();
      c.servo_start_time = servo_start;
      const auto t = Clock::now();
      obs.on_checkpoint(c, sim_);
      checkpoints_.done(seconds_since(t));
    }
    if (options_.progress_seconds > 0 && seconds_since(t_progress) >= options_.progress_seconds &&
        last.step > 0) {
      const double rate = static_cast<double>(k - k_progress) / seconds_since(t_progress);
      obs.on_progress(progress_line(st, k, last, rate));
      t_progress = Clock::now();
      k_progress = k;
    }
  }
  const bool go_on = judge.finish(k, report);
  const StageOutcome& out = report.stages.back();
  if (last.step > 0 || k > 0) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "[%s] done after %lld steps (%.1f s): %s", st.name.c_str(),
                  static_cast<long long>(k), seconds_since(t_start), out.stop_reason.c_str());
    obs.on_progress(buf);
  }
  obs.on_stage_end(out);
  sim_.set_strain_rates({});
  return go_on;
}

void StageRunner::keep_last_good(RunReport& report) const {
  if (!report.last_good) report.last_good.emplace();
  sim_.state_into(*report.last_good, false);  // sorted once, when run() returns
}

RunReport StageRunner::run(const std::vector<StageSpec>& stages, RunObserver& observer, const RunCheckpoint* resume) {
  const std::string bad = validate(options_);
  if (!bad.empty()) throw std::invalid_argument("RunOptions: " + bad);
  RunReport report;
  std::size_t first = 0;
  wall_before_ = 0.0;
  if (resume) {
    if (resume->stage_index >= stages.size())
      throw std::invalid_argument("checkpoint: stage " + std::to_string(resume->stage_index) + " of a run with " +
                                  std::to_string(stages.size()) + " stages");
    first = resume->stage_index;
    report.stages = resume->finished;
    report.steps = resume->steps;
    report.ticks = resume->ticks;
    wall_before_ = resume->wall_seconds;
    // The checkpoint was taken on a sample tick: its state is the last good one.
    if (options_.keep_last_good) keep_last_good(report);
  }
  run_start_ = Clock::now();
  checkpoints_.restart();
  for (std::size_t i = first; i < stages.size(); ++i)
    if (!run_stage(stages[i], i, observer, report, i == first ? resume : nullptr)) break;
  report.wall_seconds = wall_before_ + seconds_since(run_start_);
  if (report.last_good) dem::sort_histories(report.last_good->contacts);
  return report;
}

}  // namespace vt::protocol
