// Stiffness-normalised PID servo with anti-windup and a rate limit: the
// proportional law of proportional_servo.h plus an integral term (removes the
// steady error a constant drift leaves, e.g. shearing pushing the lateral
// stress) and a derivative term.
//
// Per controlled axis i and control update n, with the stress error
// e_n = sigma_i - target_i [Pa] (COMPRESSION POSITIVE: e > 0 means too much
// compression, so the cell must expand, i.e. a negative strain rate):
//
//   S_n  = S_{n-1} + ki * e_n                     integral term [Pa]
//   u_n  = g * e_n + S_n + kd * (e_n - e_{n-1})   [Pa]
//   rate_n = - u_n / (K_i * dt)                   [1/s], compression positive
//   |rate_n| <= max_strain_rate                   (cap; else saturated)
//   |rate_n - rate_{n-1}| <= max_rate_change      (rate limit, if > 0)
//
//   g, ki, kd   dimensionless gains (ServoParameters): g in (0, 1],
//               ki in [0, 1], kd in [0, 0.2]
//   K_i         d sigma_ii / d eps_ii [Pa], the packing's tangent modulus
//   dt          control period [s] (the rate is applied for dt)
//
// Stiffness normalisation: the strain increment of one update is
// rate_n dt = -u_n / K_i, so every gain is a fraction of the strain that
// would cancel a stress error for the current stiffness (as g in the
// proportional law), independent of the sample's stiffness and time scale.
// With constant ki, S_n = ki * sum_{j<=n} e_j. S is kept in Pa (already
// weighted by ki), so changing ki live does not make the output jump.
//
// Closed loop on a linear packing with exact K and a constant stress drift d
// per update, sigma_{n+1} = sigma_n + K rate_n dt + d:
//   e_{n+1} = e_n - u_n + d.
// - ki = kd = 0 (proportional): e_{n+1} = (1 - g) e_n + d, steady error
//   e_ss = d / g (with the sign of d).
// - ki > 0: at a steady state e_{n+1} = e_n the integral term must equal d,
//   so e_ss = 0 -- the integral removes the drift error. Characteristic
//   polynomial z^3 + (g + ki + kd - 2) z^2 + (1 - g - 2 kd) z + kd; for
//   kd = 0 the roots z^2 + (g + ki - 2) z + (1 - g) lie inside the unit circle
//   iff ki < 4 - 2g, always true for g <= 1, ki <= 1. With kd <= 0.2 all roots
//   stay inside the unit circle over the whole box g in (0, 1], ki in [0, 1]
//   (checked on a grid; the corner g = ki = 1, kd = 0.25 is marginal), which
//   is why kd is limited to [0, 0.2].
// - ki = 0, kd > 0: z^2 + (g + kd - 1) z - kd, stable iff kd < 1 - g/2.
//
// Saturation (cap and rate limit; the cap has priority):
// - cap: as in the proportional law, whenever |u_n| >= K_i dt max_strain_rate
//   (always for K_i <= 0, e.g. a loose cloud without contacts) the axis runs
//   at +-max_strain_rate in the direction of -u_n (0 when u_n = 0);
// - rate limit: the capped rate is then clipped to
//   [rate_{n-1} - max_rate_change, rate_{n-1} + max_rate_change];
// - `saturated` reports either clip.
// Anti-windup by conditional integration (clamping): when the output is
// saturated and adding ki e_n to S would push the wanted rate further beyond
// the applied one (i.e. -e_n has the sign of wanted - applied), the integral
// is NOT updated (S_n = S_{n-1}) and the output is computed with S_{n-1}.
// While the plant is held saturated the integral therefore cannot grow, so
// when the target becomes reachable the law resumes from the integral it had
// before saturation instead of overshooting to unwind a huge sum.
//
// State (per axis): S, e_{n-1}, rate_{n-1}. init() and start() clear it
// (rate_{-1} = 0: the cell is assumed at rest when control starts; the first
// update has no derivative term, so there is no derivative kick). A target
// change (set_targets) keeps it; set_parameters() keeps it too, except that
// ki = 0 clears S (ki = 0 means: no integral action).
#pragma once

#include "virtual_triaxial/control/servo_strategy.h"

namespace vt::control {

class PidServo : public ServoStrategy {
 public:
  /// Throws std::invalid_argument (see validate_servo_parameters()).
  explicit PidServo(const ServoParameters& p);

  std::string name() const override { return "pid"; }
  void init(const dem::Vec3& target_stress, const AxisMask& axes) override;
  void set_targets(const dem::Vec3& target_stress) override;
  void start(double time) override;
  /// Throws std::invalid_argument on dt <= 0 or non-finite dt, or on a
  /// non-finite stress / stiffness of a controlled axis (state unchanged).
  ServoOutput update(const ServoInput& in) override;
  void stop() override;
  const ServoParameters& parameters() const override { return p_; }
  void set_parameters(const ServoParameters& p) override;

  /// S, e_{n-1}, rate_{n-1} per axis and whether e_{n-1} exists (10 numbers).
  std::vector<double> memory() const override;
  void restore_memory(const std::vector<double>& m) override;

  /// Integral term S per axis [Pa] (0 on uncontrolled axes).
  const dem::Vec3& integral_term() const { return integral_; }

 private:
  /// Clears S, e_{n-1} and rate_{n-1}.
  void reset_state();

  ServoParameters p_;
  dem::Vec3 integral_;    ///< S [Pa]
  dem::Vec3 prev_error_;  ///< e_{n-1} [Pa]
  dem::Vec3 prev_rate_;   ///< rate_{n-1} [1/s]
  bool has_prev_ = false;
};

}  // namespace vt::control
