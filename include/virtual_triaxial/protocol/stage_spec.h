// Test stages and their stop criteria (ROS-free). Strain rates and strains
// follow the geomechanics convention: compression positive.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace vt::protocol {

enum class StageType {
  IsotropicCompression,  ///< equal compressive strain rate on every axis
  UndrainedShear,        ///< axial compression at constant volume
  Relax                  ///< no boundary motion (balancing cycles)
};

const char* to_string(StageType t);

/// A stage ends as soon as any one of its criteria is met.
struct StopCriteria {
  std::optional<double> mean_stress;    ///< p >= this [Pa]
  std::optional<double> axial_strain;   ///< eps_a since the stage start >= this [-]
  std::optional<std::int64_t> steps;    ///< steps in the stage >= this
  std::optional<double> ufr_below;      ///< UFR (eq. 66) < this, checked at samples
};

struct StageSpec {
  std::string name;
  StageType type = StageType::IsotropicCompression;
  /// eps' = eps_dot T0 (eq. 31), compression positive; or eps_dot [1/s].
  std::optional<double> strain_rate_dimensionless;
  std::optional<double> strain_rate;
  int axial_axis = 2;  ///< 0 = x, 1 = y, 2 = z
  StopCriteria stop;
};

}  // namespace vt::protocol
