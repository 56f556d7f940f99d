// Test stages, their boundary control and their stop criteria (ROS-free;
// the headless StageRunner and the ROS test_protocol_node share them).
// Strain rates, strains and stresses follow the geomechanics convention:
// compression positive. Rates are rates of the LOGARITHMIC strain.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "virtual_triaxial/control/rate_strategy.h"

namespace vt::protocol {

enum class StageType {
  IsotropicCompression,    ///< equal compressive strain rate on every axis (open loop)
  IsotropicConsolidation,  ///< servo holds every axis at confining_pressure
  DrainedShear,            ///< axial rate open loop, lateral axes servo-held at confining_pressure
  UndrainedShear,          ///< axial compression at constant volume (lateral = -axial/2)
  DrainedUnload,           ///< axial EXTENSION at the rate (open loop), lateral axes servo-held
  Relax                    ///< no boundary motion (balancing cycles)
};

const char* to_string(StageType t);
/// Parses the names printed by to_string (exact, lower case); false if unknown.
bool parse_stage_type(const std::string& name, StageType& out);
/// Every stage type name, comma separated (for error messages).
std::string stage_type_names();
/// True for the stages whose boundary is (partly) servo-controlled.
bool uses_servo(StageType t);
/// True for drained_shear and undrained_shear (they get a shear summary).
bool is_shear(StageType t);

/// "Balanced": every servo axis within stress_tolerance of its target AND
/// the unbalanced force ratio (eq. 66) below ufr_below (checked on samples).
struct BalanceCriterion {
  double stress_tolerance = 0.005;  ///< |sigma_ii - target| <= tol * target [1]
  double ufr_below = 0.01;          ///< UFR < this [1]
};

/// A stage ends as soon as any one of its criteria is met.
struct StopCriteria {
  std::optional<double> mean_stress;    ///< p >= this [Pa]
  std::optional<double> axial_strain;   ///< eps_a since the stage start >= this [-]
  std::optional<std::int64_t> steps;    ///< steps in the stage >= this
  std::optional<double> ufr_below;      ///< UFR (eq. 66) < this, checked at samples
  /// Post-peak softening: q <= (1 - softening) q_peak after a peak q_peak > 0
  /// (a fraction in (0, 1), e.g. 0.2 = 20 % below the peak).
  std::optional<double> softening;
  std::optional<BalanceCriterion> balanced;  ///< servo stages only
  std::optional<double> deviator_below;      ///< q <= this [Pa] (e.g. the end of an unloading)
};

struct StageSpec {
  std::string name;
  StageType type = StageType::IsotropicCompression;
  /// eps' = eps_dot T0 (eq. 31), compression positive; or eps_dot [1/s].
  std::optional<double> strain_rate_dimensionless;
  std::optional<double> strain_rate;
  /// Servo target of the servo-held axes [Pa] (consolidation, drained shear).
  std::optional<double> confining_pressure;
  int axial_axis = 2;  ///< 0 = x, 1 = y, 2 = z
  StopCriteria stop;
  /// The axial rate strategy (drained_shear only; `fixed` elsewhere):
  /// fixed = the rate above; predicted / adaptive start from eq. 84 (stage_judge.h).
  control::RateSpec rate_spec;

  /// Axial strain rate [1/s], compression positive (0 when none is given;
  /// the judge's first rate when `rate` is predicted or adaptive).
  double rate(double t0) const;
};

/// What the boundary of the cell does during a stage: per axis either an
/// open-loop log-strain rate [1/s, compression positive] or servo control
/// to a stress target [Pa].
struct StageBoundary {
  double open_rate[3] = {0.0, 0.0, 0.0};
  bool servo[3] = {false, false, false};
  double target[3] = {0.0, 0.0, 0.0};
  bool any_servo() const { return servo[0] || servo[1] || servo[2]; }
  std::vector<int> servo_axes() const;
};

/// Boundary of `stage` for a sample with characteristic time t0 [s]:
///   isotropic_compression   every axis open loop at +rate;
///   isotropic_consolidation every axis servo-held at confining_pressure;
///   drained_shear           axial axis open loop at +rate, the two others
///                           servo-held at confining_pressure;
///   drained_unload          like drained_shear with the axial rate reversed
///                           (extension: the deviator falls);
///   undrained_shear         axial +rate, lateral -rate/2: the log strains sum
///                           to zero, so the cell volume is constant (to
///                           round-off when each step scales L_i by
///                           exp(-r_i dt), as the runners do);
///   relax                   every axis open loop at 0.
StageBoundary stage_boundary(const StageSpec& stage, double t0);

}  // namespace vt::protocol
