// What a stage judge (stage_judge.h) remembers between ticks, as plain
// numbers, so that a checkpointed run (run_checkpoint.h) resumes with the
// judge it had, bit for bit: the largest q seen (softening criterion), the
// shear summary's accumulators (peak, the strain-weighted sums of I_mom),
// and the rate strategy's state (the current and first axial rate, the
// range of rates used, the rates of the ticks since the last sample).
// Kept apart from stage_judge.cpp so the judge's logic and its
// serialisation change independently; a rate strategy with a memory of its
// own (control/adaptive_rate.h) adds its numbers to `rate_strategy`.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "virtual_triaxial/protocol/shear_summary.h"

namespace vt::protocol {

/// The accumulators of a ShearSummaryBuilder.
struct ShearAccumulators {
  ShearSummary summary;  ///< has_data, e0, peak and end values, samples (the rest is derived)
  double sum_imom = 0, sum_weight = 0, max_imom = 0;
  double sum_imom_at_peak = 0, sum_weight_at_peak = 0, max_imom_at_peak = 0;
};

struct StageJudgeState {
  double q_peak = 0;  ///< StageMonitor: largest q so far [Pa]
  ShearAccumulators shear;
  double rate0 = 0, rate = 0;               ///< first and current axial rate [1/s]
  double rate_min = 0, rate_max = 0;        ///< |axial rate| used [1/s]
  double interval_rate_sum = 0;             ///< [1/s]
  std::int64_t interval_ticks = 0;
  bool interval_constant = true;
  std::vector<double> rate_strategy;        ///< a rate strategy's own memory (none for `fixed`)
};

/// As named numbers ("q_peak", "shear.phi_peak", ...; integers and flags
/// exactly representable) and back; from_fields() throws
/// std::invalid_argument naming a missing field.
std::map<std::string, double> to_fields(const StageJudgeState& s);
StageJudgeState from_fields(const std::map<std::string, double>& f, std::vector<double> rate_strategy);

}  // namespace vt::protocol
