// Summary of a shearing stage, built from the recorded samples:
// peak mobilized friction angle phi_peak and the axial strain at the peak,
// phi at the end, q_peak, initial void ratio e0 (at the start of shearing),
// mean moment index I_mom from the start up to the peak (chapter 6), and the
// quasi-static verdict: mean I_mom up to the peak below I_QS (default 0.1 %,
// the dissertation's quasi-static threshold, section 6).
#pragma once

#include <cstdint>

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
  double mean_moment_index_to_peak = 0;
  bool quasi_static = false;
  double quasi_static_threshold = 1e-3;  ///< I_QS used for the verdict
  std::int64_t samples = 0;
};

class ShearSummaryBuilder {
 public:
  explicit ShearSummaryBuilder(int axial_axis = 2, double i_qs = 1e-3) : axis_(axial_axis), i_qs_(i_qs) {}
  void add(const dem::Measures& m);
  ShearSummary summary() const;

 private:
  int axis_;
  double i_qs_;
  ShearSummary s_;
  double sum_imom_ = 0, sum_imom_at_peak_ = 0;
  std::int64_t n_at_peak_ = 0;
};

}  // namespace vt::protocol
