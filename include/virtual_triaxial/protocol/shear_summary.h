// Summary of a shearing stage, built from the recorded samples:
// peak mobilized friction angle phi_peak and the axial strain at the peak,
// phi at the end, q_peak, initial void ratio e0 (at the start of shearing),
// the moment index I_mom (eqs. 67-68) from the start up to the peak (mean
// and maximum), the rate strategy and the range of eps' it used, and the
// quasi-static verdict: mean I_mom up to the peak below I_QS (default 0.1 %,
// the dissertation's quasi-static threshold, section 6).
//
// The mean is over axial STRAIN, as the dissertation's (samples every 0.04 %
// strain, averaged up to the peak, section 6): each sample weighs the strain
// it covers (StageJudge's TickDecision::sample_weight). At a fixed rate the
// samples are evenly spaced in time and in strain, every weight is exactly 1
// and the mean is the plain mean of the samples; when a rate strategy changes
// the rate, a plain time mean would give the slow stretches (small I_mom)
// more weight than the strain they cover and call a run quasi-static whose
// fast stretches were not.
#pragma once

#include <cstdint>
#include <string>

#include "virtual_triaxial/dem/measures.h"

namespace vt::protocol {

struct ShearSummary {
  bool has_data = false;
  double e0 = 0;
  double phi_peak = 0;          ///< [rad]
  double eps_peak = 0;          ///< axial strain at the peak
  double q_peak = 0;            ///< [Pa]
  double phi_end = 0;           ///< [rad]
  double eps_end = 0;
  double p_end = 0, q_end = 0;  ///< [Pa]
  double mean_moment_index_to_peak = 0;  ///< strain-weighted mean I_mom, start to peak [1]
  double max_moment_index_to_peak = 0;   ///< largest sampled I_mom, start to peak [1]
  bool quasi_static = false;
  double quasi_static_threshold = 1e-3;  ///< I_QS used for the verdict
  std::string rate_strategy = "fixed";   ///< the axial rate strategy of the stage
  double strain_rate_min = 0, strain_rate_max = 0;  ///< eps' = |eps_dot_a| T0 used, smallest / largest [1]
  std::int64_t samples = 0;
};

/// How phi_peak was obtained and whether it is a quasi-static answer, in
/// words for the summary (`phi_peak_basis`): the strategy, the eps' range, and
/// the mean I_mom to the peak against I_QS (chapter 6's criterion). "" without data.
std::string phi_peak_basis(const ShearSummary& s);
struct ShearAccumulators;  // stage_judge_state.h

class ShearSummaryBuilder {
 public:
  explicit ShearSummaryBuilder(int axial_axis = 2, double i_qs = 1e-3) : axis_(axial_axis), i_qs_(i_qs) {}
  /// A recorded sample; `weight` the strain it covers relative to the others (see above).
  void add(const dem::Measures& m, double weight = 1.0);
  ShearSummary summary() const;
  /// Its sums and peak, for a checkpoint (stage_judge_state.h), and back.
  ShearAccumulators accumulators() const;
  void restore(const ShearAccumulators& a);

 private:
  int axis_;
  double i_qs_;
  ShearSummary s_;
  double sum_imom_ = 0, sum_weight_ = 0, max_imom_ = 0;
  double sum_imom_at_peak_ = 0, sum_weight_at_peak_ = 0, max_imom_at_peak_ = 0;
};

}  // namespace vt::protocol
