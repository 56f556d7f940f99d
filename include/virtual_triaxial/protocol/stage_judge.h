// The stage judge: every decision of one stage that does not depend on how
// the specimen is stepped (ROS-free). The headless StageRunner and the rig's
// ProtocolSession both build one per stage and feed it the same numbers, so
// "the same decisions, tick for tick" holds by construction:
//   - which ticks are sample ticks (recorded; UFR criteria judged);
//   - per tick, in this order: a stop request (abort / preempt) ends the
//     stage; else a met stop criterion (stage_monitor.h); else the step cap
//     (the stage's `steps` criterion, or RunOptions::max_steps_per_stage when
//     it has none) ends the run with the verdict `step_limit`;
//   - the axial strain rate of the loading axis for the next tick: the
//     stage's rate strategy (control/rate_strategy.h: fixed, predicted,
//     adaptive) fed the tick's I_mom; the first rate of `predicted` and
//     `adaptive` is eq. 84's eps'_QS at target x I_QS for the specimen at the
//     stage start (SpecimenAtStart) divided by T0 (eq. 85);
//   - the stage's outcome, the run's verdict and failure message, and the
//     shear summary (shear_summary.h) with the strategy and the range of
//     eps' = |eps_dot_a| T0 (eq. 31) it used.
// Threads: decide() (with fail()) and record() touch disjoint state (the rig
// calls decide() from its tick thread and record() from the session thread);
// each is called in tick order and never concurrently with itself. finish()
// is called once, after both have stopped.
// Units SI; rates are log-strain rates [1/s], compression positive.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "virtual_triaxial/control/rate_strategy.h"
#include "virtual_triaxial/dem/measures.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/protocol/shear_summary.h"
#include "virtual_triaxial/protocol/stage_judge_state.h"
#include "virtual_triaxial/protocol/stage_monitor.h"
#include "virtual_triaxial/protocol/stage_runner.h"
#include "virtual_triaxial/protocol/stage_spec.h"

namespace vt::protocol {

/// The decision on one control tick of a stage: go on, or end the stage.
struct TickDecision {
  enum class Kind { Continue, Criterion, StepLimit, Stop };
  Kind kind = Kind::Continue;
  std::string why;          ///< "" while the stage goes on; the stop reason, "step limit", "aborted" or "preempted"
  TickSample sample;        ///< what the stop criteria saw (stage steps, eps_a, p, q, ...)
  bool sample_tick = false; ///< a sample tick (recorded; UFR criteria judged)
  /// Weight of this tick's sample in the mean I_mom to the peak: the axial
  /// strain covered since the previous sample, relative to the stage's first
  /// rate (exactly 1 while the rate never changed). Set when the tick is
  /// recorded (a sample tick or the stage's last tick).
  double sample_weight = 1.0;
  double axial_rate = 0.0;  ///< the axial rate of the NEXT tick [1/s] (the rate strategy's command)
  bool ends_stage() const { return kind != Kind::Continue; }
};

/// The specimen at the start of a stage, for the eq. 84 prediction of the
/// `predicted` and `adaptive` rate strategies (0 = not known).
struct SpecimenAtStart {
  double void_ratio = 0.0;        ///< e0 [-]
  double dispersity_index = 0.0;  ///< Delta (eq. 80) [-]
};

/// The specimen of `sim` now: void ratio from the cell and solid volumes,
/// Delta from the particles' radii (quasi_static/dispersity_index.h). One home
/// for triax_run and dem_node's get_info.
SpecimenAtStart specimen_at_start(const dem::Simulation& sim);

class StageJudge {
 public:
  /// `t0` the sample's characteristic time [s] (eq. 91-92). Throws
  /// std::invalid_argument naming the option when `options` are bad, and
  /// naming `stages[].rate` when its strategy needs a specimen that is not
  /// given or outside eq. 84's domain.
  StageJudge(const StageSpec& stage, const RunOptions& options, double t0, const SpecimenAtStart& specimen = {});

  const StageSpec& stage() const { return stage_; }
  const StageBoundary& boundary() const { return boundary_; }
  /// Stage step count at which the stage is capped.
  std::int64_t step_cap() const { return cap_; }
  /// True when the tick that ends after `stage_steps` steps is a sample tick.
  bool is_sample_tick(std::int64_t stage_steps) const;
  /// Axial rate for the first tick [1/s] (later ones: TickDecision::axial_rate).
  double first_axial_rate() const { return rate0_; }
  /// True when decide() needs TickSample::moment_index on every tick.
  bool needs_moment_index() const { return needs_index_; }
  /// The rate strategy's name ("fixed" for stages without an axial rate).
  const char* strategy_name() const { return strategy_ ? strategy_->name() : "fixed"; }

  /// Judges one tick from the specimen's state at its end; `stop_request`
  /// is nullptr, "aborted" or "preempted". `s.stage_steps` must be the
  /// steps since the stage start; s.ufr / s.contacts only on sample ticks.
  TickDecision decide(const TickSample& s, const char* stop_request);
  /// A recorded sample (a sample tick, or the stage's last tick) with the
  /// decision of its tick: feeds the shear summary of shear stages.
  void record(const dem::Measures& m, const TickDecision& d);
  /// The stage fails outside the judge's criteria (numerical failure, a rig
  /// that stops answering): `failure` is the run's failure message.
  void fail(Verdict verdict, const std::string& failure, const std::string& stop_reason);

  /// Ends the stage after `steps` stage steps: appends its outcome to the
  /// report, adds the steps, sets the run's verdict and failure when the
  /// stage ended the run, and the shear summary of a shear stage. Returns
  /// true when the run goes on to the next stage.
  bool finish(std::int64_t steps, RunReport& report);

  /// What the judge remembers between ticks (stage_judge_state.h; defined in
  /// stage_judge_state.cpp), for a checkpoint, and back into a judge built
  /// for the same stage. Not while decide() or record() runs.
  StageJudgeState save_state() const;
  void restore_state(const StageJudgeState& s);

 private:
  StageSpec stage_;
  StageBoundary boundary_;
  StageMonitor monitor_;
  ShearSummaryBuilder shear_;
  StageOutcome out_;
  std::int64_t control_interval_, sample_interval_, cap_;
  double t0_;
  // decide()'s state: the rate strategy and the strain each sample covers.
  std::unique_ptr<control::RateStrategy> strategy_;  ///< null without an open-loop axial rate
  bool needs_index_ = false;                         ///< the strategy reads I_mom (adaptive)
  double quasi_static_threshold_ = 1e-3;
  double rate0_ = 0.0, rate_ = 0.0;
  double rate_min_ = 0.0, rate_max_ = 0.0;  ///< |axial rate| used [1/s]
  double interval_rate_sum_ = 0.0;          ///< sum of the rates of the ticks since the last sample
  std::int64_t interval_ticks_ = 0;
  bool interval_constant_ = true;           ///< every tick since the last sample at rate0_
  // the end
  Verdict verdict_ = Verdict::Completed;
  std::string failure_;
};

}  // namespace vt::protocol
