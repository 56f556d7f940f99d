// Stop criteria of one stage, judged once per control tick (ROS-free; the
// headless StageRunner and the ROS test_protocol_node feed it the same
// numbers, so both end a stage on the same tick).
//
// Cadence: the cheap criteria (steps, mean stress, axial strain, post-peak
// softening) are judged on every control tick; the ones that need the
// unbalanced force ratio (ufr_below, balanced) only on sample ticks, where a
// sample tick is the first tick of the stage and every tick whose stage step
// count is a multiple of the output interval (is_sample_tick()).
// Units SI, compression positive.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "virtual_triaxial/protocol/stage_spec.h"

namespace vt::protocol {

/// The state of the specimen at the end of one control tick.
struct TickSample {
  std::int64_t stage_steps = 0;  ///< DEM steps since the stage start
  double eps_a = 0;              ///< axial log strain since the stage start [1]
  double p = 0, q = 0;           ///< mean and deviator stress [Pa]
  double stress[3] = {0, 0, 0};  ///< sigma_xx, sigma_yy, sigma_zz [Pa]
  std::optional<double> ufr;     ///< unbalanced force ratio (eq. 66), on sample ticks
  std::int64_t contacts = 0;     ///< contacts (UFR criteria need > 0), on sample ticks
  /// I_mom (eqs. 67-68) at the tick's end: on every tick of a stage whose
  /// rate strategy reads it (StageJudge::needs_moment_index), else on sample ticks.
  std::optional<double> moment_index;
  /// The axial rate the tick ran at [1/s], when the runner does not apply the
  /// judge's command itself (the rig: an external rate controller node).
  std::optional<double> applied_axial_rate;
};

/// True when the tick that ends after `stage_steps` steps of the stage
/// (control ticks of `tick_steps` steps) is a sample tick.
bool is_sample_tick(std::int64_t stage_steps, std::int64_t tick_steps, std::int64_t sample_interval);

class StageMonitor {
 public:
  StageMonitor(const StageSpec& stage, const StageBoundary& boundary)
      : stage_(stage), boundary_(boundary) {}
  /// "" while the stage goes on, else the reason it ends (readable).
  std::string check(const TickSample& s);
  /// Largest q seen so far [Pa].
  double q_peak() const { return q_peak_; }
  /// A resumed run's largest q so far [Pa] (checkpoint, stage_judge_state.h).
  void restore_q_peak(double q) { q_peak_ = q; }

 private:
  StageSpec stage_;
  StageBoundary boundary_;
  double q_peak_ = 0.0;
};

}  // namespace vt::protocol
