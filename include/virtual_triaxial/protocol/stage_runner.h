// Runs a sequence of test stages on a Simulation (ROS-free; the headless
// triax_run and the ROS protocol node share it).
//
// The run is cut into control ticks of RunOptions::control_interval DEM
// steps, exactly like dem_node's ticks (publish_every), so a protocol run
// headless and through the ROS rig takes the same decisions on the same
// ticks. Per tick:
//   1. the boundary of the stage (stage_spec.h: stage_boundary) gives each
//      axis an open-loop log-strain rate r or servo control; servo axes use
//      the rate the servo returned after the previous tick (0 on the first
//      tick of a stage, like a controller that answers from the next tick);
//   2. the cell's velocity gradient is l_i = expm1(-r_i dt) / dt (extension
//      positive), so every step scales L_i by exp(-r_i dt) and changes the
//      log strain by exactly r_i dt (undrained: volume constant to round-off);
//   3. control_interval DEM steps; the last one is measured when the tick
//      ends on a sample, runs a servo or the ticks are longer than one step;
//   4. servo update (control::ServoStrategy) from the tick-end stress and
//      axis stiffness, dt = control period = control_interval * dt;
//   5. the stage judge (stage_judge.h, shared with the rig): abort, stop
//      criteria, step cap, the axial rate of the next tick, and at the end
//      the stage outcome, the verdict and the shear summary.
// The cell's strain reference is reset at the start of every stage, so
// strains in the samples are measured from the stage start. Numerical
// failure ends the run with `unstable`; abort() (from another thread or an
// observer) ends it with `aborted` on the next tick the judge sees.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "virtual_triaxial/control/servo_strategy.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/protocol/checkpoint_schedule.h"
#include "virtual_triaxial/protocol/shear_summary.h"
#include "virtual_triaxial/protocol/stage_monitor.h"
#include "virtual_triaxial/protocol/stage_spec.h"
#include "virtual_triaxial/quasi_static/qs_rate_prediction.h"

namespace vt::protocol {

/// Preempted: the ROS action was cancelled (the headless runner never ends so).
enum class Verdict { Completed, Unstable, StepLimit, Aborted, Preempted };
const char* to_string(Verdict v);

struct StageOutcome {
  std::string name;
  StageType type = StageType::Relax;
  std::int64_t steps = 0;
  std::string stop_reason;
};

/// The servo of servo-controlled stages (consolidation, drained shear).
struct ServoSettings {
  std::string strategy = "proportional";   ///< control::make_servo name
  /// gain, ki, kd as given; max_strain_rate is set from max_dimensionless_rate / T0 and
  /// max_rate_change [1/s] from max_dimensionless_rate_change / T0 when a stage starts.
  control::ServoParameters parameters;
  double max_dimensionless_rate_change = 0.0;  ///< |delta rate| T0 per update, 0 = off (servo node ~max_rate_change)
  double max_dimensionless_rate = 1e-4;    ///< cap on |eps'| of the servo rates
};

struct RunOptions {
  std::int64_t control_interval = 1;       ///< DEM steps per control tick (dem_node publish_every)
  ServoSettings servo;
  std::int64_t sample_interval = 100;      ///< steps between recorded samples
  double progress_seconds = 2.0;           ///< wall seconds between progress lines
  std::int64_t max_steps_per_stage = 50'000'000;
  bool keep_last_good = true;              ///< snapshot the state at every good sample
  double quasi_static_threshold = 1e-3;    ///< I_QS for the shear summary and the rate strategies
  /// For the eq. 84 prediction of the `predicted` / `adaptive` rate strategies:
  double young_modulus = 0.0;              ///< E of the specimen [Pa] (0 = not known)
  quasi_static::QsDamping qs_damping = quasi_static::QsDamping::OD;  ///< ND for ND damping, else OD
  /// Checkpoints inside a stage (run_checkpoint.h, RunObserver::on_checkpoint),
  /// due as checkpoint_schedule.h says: on the first sample tick after
  /// checkpoint_ticks control ticks or checkpoint_seconds wall seconds since
  /// the last one (0 = that trigger off), never sooner than
  /// kCheckpointCostFactor x the wall time the last one took.
  std::int64_t checkpoint_ticks = 0;
  double checkpoint_seconds = 0.0;
};

struct RunCheckpoint;  // run_checkpoint.h

struct RunReport {
  Verdict verdict = Verdict::Completed;
  std::string failure;                     ///< reason when not completed
  std::vector<StageOutcome> stages;
  std::int64_t steps = 0;
  std::int64_t ticks = 0;
  double wall_seconds = 0;
  ShearSummary shear;                      ///< of the last shear stage (drained or undrained)
  std::optional<dem::SimulationState> last_good;
};

/// Receives samples and progress; all callbacks optional.
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  virtual void on_stage_start(const StageSpec&, const dem::Simulation&) {}
  virtual void on_sample(const StageSpec&, const dem::Measures&) {}
  virtual void on_progress(const std::string&) {}
  virtual void on_stage_end(const StageOutcome&) {}
  /// A checkpoint is due (see RunOptions::checkpoint_ticks): `sim` holds the
  /// state that goes with it. A throw ends the run (e.g. a full disk).
  virtual void on_checkpoint(const RunCheckpoint&, const dem::Simulation&) {}
};

class StageRunner {
 public:
  StageRunner(dem::Simulation& sim, const RunOptions& options)
      : sim_(sim), options_(options), checkpoints_(options.checkpoint_ticks, options.checkpoint_seconds) {}
  /// Throws std::invalid_argument naming the option when RunOptions are bad.
  /// `resume`: continue a checkpointed run (the Simulation must hold the
  /// checkpoint's state); the stages are the run's, from the first.
  RunReport run(const std::vector<StageSpec>& stages, RunObserver& observer, const RunCheckpoint* resume = nullptr);
  /// Ends the run at the next tick with the verdict `aborted` (thread-safe).
  void abort() { abort_ = true; }

 private:
  /// Returns false when the run must end (instability, step limit, abort).
  bool run_stage(const StageSpec& stage, std::size_t index, RunObserver& observer, RunReport& report,
                 const RunCheckpoint* resume);
  std::string progress_line(const StageSpec& stage, std::int64_t k, const dem::Measures& m, double rate) const;
  /// The simulation's state into report.last_good, reusing the storage of
  /// the one kept before (dem::Simulation::state_into), its contacts in
  /// list order: run() sorts them once before it returns the report.
  void keep_last_good(RunReport& report) const;

  dem::Simulation& sim_;
  RunOptions options_;
  std::atomic<bool> abort_{false};
  CheckpointSchedule checkpoints_;
  std::chrono::steady_clock::time_point run_start_{};
  double wall_before_ = 0.0;      ///< a resumed run's wall time before the resume [s]
};

/// Checks RunOptions; "" or "<option>: <reason>".
std::string validate(const RunOptions& o);

}  // namespace vt::protocol
