#include "virtual_triaxial/dem/stability_monitor.h"

#include <cmath>
#include <sstream>

namespace vt::dem {

std::string StabilityMonitor::check(bool finite, double max_overlap_ratio, const EnergyBudget& e) const {
  if (!finite || !std::isfinite(e.kinetic()) || !std::isfinite(e.elastic))
    return "non-finite velocity, position or energy (NaN/inf)";
  if (max_overlap_ratio > limits_.max_overlap_ratio) {
    std::ostringstream s;
    s << "overlap " << max_overlap_ratio << " of the smaller radius exceeds the limit "
      << limits_.max_overlap_ratio;
    return s.str();
  }
  const double err = -e.balance_error();  // energy created from nothing
  const double scale = e.scale();
  if ((scale > 0.0 && err > limits_.max_energy_error * scale) ||
      (scale == 0.0 && e.kinetic() + e.elastic > 0.0)) {
    std::ostringstream s;
    s << "kinetic-energy blow-up: energy balance error " << err << " J against " << scale
      << " J that flowed";
    return s.str();
  }
  return {};
}

}  // namespace vt::dem
