// Servo control of the cell stress (DESIGN §6, `servo_controller_node`):
// one interface, each control law a small class behind it.
//
// A strategy turns the measured normal stresses of the periodic cell into
// strain rates of the cell axes it controls, once per control update:
//
//   init(targets, axes)  -> set_targets(...)* -> start(t) -> update(in)* -> stop()
//
// Units SI, geomechanics sign convention (DESIGN §2): stresses [Pa] and
// strain rates [1/s] are COMPRESSION POSITIVE, so a positive strain rate
// shrinks the axis. The controller never touches the DEM core; the caller
// (DEM loop or ROS node) applies the returned rates to the cell.
//
// Lifecycle errors (update before start, start before init, ...) throw
// std::logic_error; bad values (non-finite stress, dt <= 0, bad parameters)
// throw std::invalid_argument naming the offending quantity.
//
// ROS-free (DESIGN §1): no ROS headers here or in src/control/.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "virtual_triaxial/dem/vec3.h"

namespace vt::control {

/// Which cell axes a strategy controls (closed loop). Uncontrolled axes get
/// strain rate 0 and error 0 from update(); another owner drives them.
struct AxisMask {
  bool x = true, y = true, z = true;
  /// Axis i = 0 (x), 1 (y), 2 (z); throws std::out_of_range otherwise.
  bool operator[](int i) const;
};

/// Tuning of a servo strategy. Validated by validate_servo_parameters() (the
/// factory and every strategy constructor call it).
struct ServoParameters {
  /// Dimensionless gain g in (0, 1]: fraction of the current stress error the
  /// proportional law tries to cancel per DEM step (g = 1 cancels it in one
  /// step if the stiffness estimate is exact; > 1 overshoots and is unstable).
  double gain = 0.5;
  /// Cap on |strain rate| of every controlled axis [1/s], finite and > 0
  /// (no default: it depends on the time scale of the sample; it bounds the
  /// strain increment per step to max_strain_rate * dt and is the rate used
  /// when the packing has no stiffness, e.g. a loose cloud without contacts).
  double max_strain_rate = 0.0;

  // ---- PID terms (strategy "pid", pid_servo.h; ignored by "proportional").
  // The defaults (0, 0, 0) make the PID law identical to the proportional one.
  // Like `gain`, ki and kd act on the stiffness-normalised error e / K_i, so
  // they are dimensionless and independent of the sample's stiffness and of
  // the control period.
  /// Integral gain ki in [0, 1]: fraction of the current error added to the
  /// integral term every control update (its steady contribution cancels a
  /// constant drift d per update when ki * sum(e) = d).
  double ki = 0.0;
  /// Derivative gain kd in [0, 0.2], on the error change per update
  /// e_n - e_{n-1}. The bounds keep the loop stable on an exactly known
  /// linear packing for every g in (0, 1] and ki in [0, 1] (pid_servo.h).
  double kd = 0.0;
  /// Rate limit [1/s]: cap on |rate_n - rate_{n-1}| per control update and
  /// axis, finite and >= 0; 0 = no limit.
  double max_rate_change = 0.0;
};

/// Throws std::invalid_argument naming the field ("gain", "max_strain_rate",
/// "ki", "kd", "max_rate_change") when a value is out of range or not finite.
void validate_servo_parameters(const ServoParameters& p);

/// The stiffness-normalised rate both laws share: the compression-positive
/// strain rate [1/s] that would cancel the stress correction u [Pa] in one
/// update for tangent modulus k [Pa] and update interval dt [s], i.e. -u/(k dt)
/// while |u| < k dt cap, otherwise +-infinity in the direction that reduces
/// u (always for k <= 0: no division by a zero or tiny stiffness); 0 for
/// u = 0. The caller clamps it to +-cap.
double stiffness_normalised_rate(double u, double k, double dt, double cap);

/// One control update.
struct ServoInput {
  double time = 0.0;   ///< simulation time [s]
  double dt = 0.0;     ///< DEM time step [s], > 0 (the rate is applied for dt)
  dem::Vec3 stress;    ///< measured sigma_xx, sigma_yy, sigma_zz [Pa], compression positive
  /// d sigma_ii / d eps_ii [Pa] per axis: the packing's current tangent
  /// modulus for that axis (>= 0; 0 when there are no contacts).
  dem::Vec3 stiffness;
};

/// Result of one control update.
struct ServoOutput {
  dem::Vec3 strain_rate;                    ///< [1/s], compression positive; 0 on uncontrolled axes
  dem::Vec3 error;                          ///< sigma - target [Pa]; 0 on uncontrolled axes
  /// rate clipped at +-max_strain_rate (or, for "pid", by max_rate_change)
  bool saturated[3] = {false, false, false};
};

class ServoStrategy {
 public:
  virtual ~ServoStrategy() = default;

  /// Registry name of the strategy (as accepted by make_servo()).
  virtual std::string name() const = 0;
  /// Sets the stress targets [Pa] (finite, compression positive) and the
  /// controlled axes; leaves the strategy stopped.
  virtual void init(const dem::Vec3& target_stress, const AxisMask& axes) = 0;
  /// Changes the targets [Pa] (e.g. a pressure ramp); requires init().
  virtual void set_targets(const dem::Vec3& target_stress) = 0;
  /// Starts closed-loop control at simulation time `time` [s]; requires init().
  virtual void start(double time) = 0;
  /// Strain rates for the controlled axes, 0 for the others; requires start().
  virtual ServoOutput update(const ServoInput& in) = 0;
  /// Stops control (update() throws until the next start()).
  virtual void stop() = 0;
  /// Current tuning.
  virtual const ServoParameters& parameters() const = 0;
  /// Changes the tuning from the next update() on (live tuning), keeping the
  /// controller's state (targets, axes, running, any integral / previous
  /// rate), so the switch is bumpless where the law allows it. Throws
  /// std::invalid_argument naming the field (validate_servo_parameters())
  /// and then keeps the old tuning.
  virtual void set_parameters(const ServoParameters& p) = 0;

  /// The controller's memory between updates (e.g. the PID's integral,
  /// previous error and rate), as numbers restored bit for bit by
  /// restore_memory() after init() and start(): a checkpointed run resumes
  /// with the servo it had (protocol/run_checkpoint.h). Empty for a
  /// stateless law. restore_memory() throws std::invalid_argument on a
  /// vector of the wrong length.
  virtual std::vector<double> memory() const { return {}; }
  virtual void restore_memory(const std::vector<double>& m);

  /// Relative tolerance check: |sigma_i - target_i| <= tol * |target_i| on
  /// every controlled axis (true when no axis is controlled; false for a NaN
  /// stress). tol >= 0 and finite; requires init().
  bool within(const dem::Vec3& stress, double tol) const;

  bool initialised() const { return initialised_; }
  bool running() const { return running_; }
  const dem::Vec3& targets() const { return targets_; }
  const AxisMask& axes() const { return axes_; }

 protected:
  /// Checks the targets (finite) and stores them; for init()/set_targets().
  void store_targets(const dem::Vec3& target_stress);
  /// Throws std::logic_error naming `what` unless init() has been called.
  void require_initialised(const char* what) const;

  dem::Vec3 targets_;
  AxisMask axes_;
  bool initialised_ = false;
  bool running_ = false;
};

/// Builds the strategy called `name` ("proportional", "pid"). Throws
/// std::invalid_argument naming the bad parameter, or the unknown strategy
/// name together with the known ones.
std::unique_ptr<ServoStrategy> make_servo(const std::string& name, const ServoParameters& p);

}  // namespace vt::control
