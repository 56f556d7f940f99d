// Stiffness-normalised proportional servo: the cell-pressure law of PFC and
// YADE, written for a periodic cell.
//
// Per controlled axis i, with the stress error e_i = sigma_i - target_i [Pa]
// (compression positive: e_i > 0 means too much compression, so the cell must
// EXPAND, i.e. a negative compression-positive strain rate):
//
//   strain_rate_i = - g * e_i / (K_i * dt)          [1/s]
//   |strain_rate_i| <= max_strain_rate               (else clipped, saturated)
//
//   g       dimensionless gain, 0 < g <= 1
//   K_i     d sigma_ii / d eps_ii [Pa], the packing's current tangent modulus
//   dt      DEM time step [s]
//
// The strain increment of one step, strain_rate_i * dt = -g e_i / K_i, is g
// times the one that would cancel the error if the packing responded with
// its current tangent stiffness. For a linear response the error therefore
// decays geometrically, e_{n+1} = (1 - g) e_n: g = 1 cancels it in one step
// when K_i is exact, 1 < g < 2 overshoots and oscillates, g >= 2 does not
// converge; hence g is restricted to (0, 1]. For a stiffening (Hertz-like)
// packing the tangent K_i underestimates the secant stiffness of a loading
// step (so g = 1 would overshoot) and overestimates it when unloading, so
// g < 1 (default 0.5) is the safe choice.
//
// This is PFC's wall servo  velocity = g (sigma - target) A / (K_wall dt)
// with the wall area A and the contact stiffness on the wall K_wall [N/m]
// replaced, for a periodic cell without walls, by the stress-per-strain
// stiffness K_i of the whole packing (A / K_wall -> 1 / K_i, velocity ->
// strain rate). Yousefi (2017), "Input parameters in discrete element
// modeling", section 4.3.3 (compression phase) describes the force-controlled
// servo mechanism used to bring a sample to the confining pressure.
//
// No / tiny stiffness (loose cloud, no contacts): whenever the law would need
// a rate at or beyond the cap, i.e. g |e_i| >= K_i dt max_strain_rate
// (always true for K_i <= 0), the axis runs at the cap in the direction that
// reduces the error (compress at max rate below target, expand above) and is
// reported saturated. A zero error gives rate 0. A negative K_i (a noisy
// tangent estimate past the peak) is treated like K_i = 0.
//
// The PID terms of ServoParameters (ki, kd, max_rate_change) are ignored
// here; PidServo (pid_servo.h) with ki = kd = max_rate_change = 0 gives the
// same rates as this law, bit for bit.
#pragma once

#include "virtual_triaxial/control/servo_strategy.h"

namespace vt::control {

class ProportionalServo : public ServoStrategy {
 public:
  /// Throws std::invalid_argument (see validate_servo_parameters()).
  explicit ProportionalServo(const ServoParameters& p);

  std::string name() const override { return "proportional"; }
  void init(const dem::Vec3& target_stress, const AxisMask& axes) override;
  void set_targets(const dem::Vec3& target_stress) override;
  void start(double time) override;
  /// Throws std::invalid_argument on dt <= 0 or non-finite dt, or on a
  /// non-finite stress / stiffness of a controlled axis.
  ServoOutput update(const ServoInput& in) override;
  void stop() override;

  const ServoParameters& parameters() const override { return p_; }
  /// The law is stateless: the new gain / cap apply from the next update().
  /// ki, kd and max_rate_change are validated but ignored.
  void set_parameters(const ServoParameters& p) override;
  /// Time passed to the last start() [s].
  double start_time() const { return start_time_; }

 private:
  ServoParameters p_;
  double start_time_ = 0.0;
};

}  // namespace vt::control
