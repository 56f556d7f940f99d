#include "virtual_triaxial/protocol/shear_summary.h"

#include <cstdio>

namespace vt::protocol {

void ShearSummaryBuilder::add(const dem::Measures& m, double weight) {
  if (!s_.has_data) {
    s_.has_data = true;
    s_.e0 = m.void_ratio;
  }
  ++s_.samples;
  sum_imom_ += weight * m.moment_index;  // weight 1: exactly the plain sum
  sum_weight_ += weight;
  if (m.moment_index > max_imom_ || s_.samples == 1) max_imom_ = m.moment_index;
  const double eps = m.strain[axis_];
  if (m.phi > s_.phi_peak || s_.samples == 1) {
    s_.phi_peak = m.phi;
    s_.eps_peak = eps;
    s_.q_peak = m.q;
    sum_imom_at_peak_ = sum_imom_;
    sum_weight_at_peak_ = sum_weight_;
    max_imom_at_peak_ = max_imom_;
  }
  s_.phi_end = m.phi;
  s_.eps_end = eps;
  s_.p_end = m.p;
  s_.q_end = m.q;
}

ShearSummary ShearSummaryBuilder::summary() const {
  ShearSummary s = s_;
  s.mean_moment_index_to_peak = sum_weight_at_peak_ > 0 ? sum_imom_at_peak_ / sum_weight_at_peak_ : 0.0;
  s.max_moment_index_to_peak = max_imom_at_peak_;
  s.quasi_static_threshold = i_qs_;
  s.quasi_static = s.has_data && s.mean_moment_index_to_peak < i_qs_;
  return s;
}

std::string phi_peak_basis(const ShearSummary& s) {
  if (!s.has_data) return "";
  char rate[120];
  if (s.strain_rate_min == s.strain_rate_max)
    std::snprintf(rate, sizeof rate, "at eps' %.3g", s.strain_rate_min);
  else
    std::snprintf(rate, sizeof rate, "at eps' %.3g to %.3g", s.strain_rate_min, s.strain_rate_max);
  char buf[480];
  if (s.quasi_static)
    std::snprintf(buf, sizeof buf,
                  "measured directly in a quasi-static shear (rate strategy %s, %s): mean I_mom to the peak %.3g < "
                  "I_QS %.3g",
                  s.rate_strategy.c_str(), rate, s.mean_moment_index_to_peak, s.quasi_static_threshold);
  else
    std::snprintf(buf, sizeof buf,
                  "measured in a shear that is NOT quasi-static (rate strategy %s, %s): mean I_mom to the peak %.3g "
                  ">= I_QS %.3g, so phi_peak is above the quasi-static value; use rate.strategy adaptive or "
                  "`triax_qs predict`",
                  s.rate_strategy.c_str(), rate, s.mean_moment_index_to_peak, s.quasi_static_threshold);
  return buf;
}

}  // namespace vt::protocol
