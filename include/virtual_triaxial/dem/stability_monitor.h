// Detection of numerical failure (DESIGN §9). A step is judged unstable when
//   - a velocity or position is not finite (NaN / inf);
//   - an overlap exceeds `max_overlap_ratio` times the smaller radius;
//   - the energy balance is broken: W - (dKE + dU + D + Fr) exceeds
//     `max_energy_error` times everything that flowed (kinetic-energy
//     blow-up creates energy from nothing).
// The thresholds are dimensionless, so the dimensionless invariance holds.
#pragma once

#include <string>

#include "virtual_triaxial/dem/measures.h"

namespace vt::dem {

struct StabilityLimits {
  double max_overlap_ratio = 0.1;
  double max_energy_error = 0.5;
};

class StabilityMonitor {
 public:
  explicit StabilityMonitor(StabilityLimits limits = {}) : limits_(limits) {}
  /// Empty string when the state is sane, otherwise the reason.
  std::string check(bool finite, double max_overlap_ratio, const EnergyBudget& e) const;
  const StabilityLimits& limits() const { return limits_; }

 private:
  StabilityLimits limits_;
};

}  // namespace vt::dem
