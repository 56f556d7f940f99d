// Runs a sequence of test stages on a Simulation (ROS-free; the headless
// triax_run and the ROS protocol node share it).
//
// Boundary control per stage (compression positive rates in, mechanics
// convention inside the cell):
//   isotropic_compression  every axis at -eps_dot;
//   undrained_shear        axial axis at -eps_dot, lateral axes at
//                          (1/sqrt(1 - eps_dot dt) - 1)/dt, which keeps the
//                          cell volume constant step by step to round-off
//                          (plain -eps_a_dot/2 drifts at O(eps_dot^2 dt^2));
//   relax                  no boundary motion.
// The cell's strain reference is reset at the start of every stage, so
// strains in the samples are measured from the stage start.
// Stop criteria are checked after every step (mean stress, axial strain,
// step count) or at every sample (UFR). A stage without a `steps` criterion
// is capped at RunOptions::max_steps_per_stage and the run ends with the
// verdict `step_limit`. Numerical failure ends the run with `unstable`.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/protocol/shear_summary.h"
#include "virtual_triaxial/protocol/stage_spec.h"

namespace vt::protocol {

enum class Verdict { Completed, Unstable, StepLimit };
const char* to_string(Verdict v);

struct StageOutcome {
  std::string name;
  StageType type = StageType::Relax;
  std::int64_t steps = 0;
  std::string stop_reason;
};

struct RunOptions {
  std::int64_t sample_interval = 100;      ///< steps between recorded samples
  double progress_seconds = 2.0;           ///< wall seconds between progress lines
  std::int64_t max_steps_per_stage = 50'000'000;
  bool keep_last_good = true;              ///< snapshot the state at every good sample
  double quasi_static_threshold = 1e-3;    ///< I_QS for the shear summary
};

struct RunReport {
  Verdict verdict = Verdict::Completed;
  std::string failure;                     ///< reason when not completed
  std::vector<StageOutcome> stages;
  std::int64_t steps = 0;
  double wall_seconds = 0;
  ShearSummary shear;                      ///< of the last undrained_shear stage
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
};

class StageRunner {
 public:
  StageRunner(dem::Simulation& sim, const RunOptions& options) : sim_(sim), options_(options) {}
  RunReport run(const std::vector<StageSpec>& stages, RunObserver& observer);

 private:
  /// Returns false when the run must end (instability or step limit).
  bool run_stage(const StageSpec& stage, RunObserver& observer, RunReport& report);
  void apply_rates(const StageSpec& stage);
  std::string stop_reason(const StageSpec& stage, std::int64_t k, const dem::Measures* sample) const;
  std::string progress_line(const StageSpec& stage, std::int64_t k, const dem::Measures& m, double rate) const;

  dem::Simulation& sim_;
  RunOptions options_;
  double axial_start_ = 0;  ///< cell edge length at the stage start
};

}  // namespace vt::protocol
