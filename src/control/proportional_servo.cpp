// Stiffness-normalised proportional servo; the law and its reference are in
// proportional_servo.h.
#include "virtual_triaxial/control/proportional_servo.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vt::control {

namespace {
const char* const kAxisName[3] = {"x", "y", "z"};
}  // namespace

ProportionalServo::ProportionalServo(const ServoParameters& p) : p_(p) {
  validate_servo_parameters(p_);
}

void ProportionalServo::init(const dem::Vec3& target_stress, const AxisMask& axes) {
  store_targets(target_stress);
  axes_ = axes;
  initialised_ = true;
  running_ = false;
}

void ProportionalServo::set_targets(const dem::Vec3& target_stress) {
  require_initialised("set_targets()");
  store_targets(target_stress);
}

void ProportionalServo::start(double time) {
  require_initialised("start()");
  start_time_ = time;
  running_ = true;
}

void ProportionalServo::stop() { running_ = false; }

void ProportionalServo::set_parameters(const ServoParameters& p) {
  validate_servo_parameters(p);
  p_ = p;
}

ServoOutput ProportionalServo::update(const ServoInput& in) {
  if (!running_)
    throw std::logic_error("servo 'proportional': update() called while not started");
  if (!(std::isfinite(in.dt) && in.dt > 0.0))
    throw std::invalid_argument("servo 'proportional': dt must be finite and > 0, got " +
                                std::to_string(in.dt));
  ServoOutput out;
  for (int i = 0; i < 3; ++i) {
    if (!axes_[i]) continue;  // rate, error 0; not saturated
    if (!std::isfinite(in.stress[i]) || !std::isfinite(in.stiffness[i]))
      throw std::invalid_argument(std::string("servo 'proportional': stress/stiffness.") +
                                  kAxisName[i] + " is not finite");
    const double e = in.stress[i] - targets_[i];
    out.error[i] = e;
    const double wanted = stiffness_normalised_rate(p_.gain * e, in.stiffness[i], in.dt, p_.max_strain_rate);
    out.strain_rate[i] = std::clamp(wanted, -p_.max_strain_rate, p_.max_strain_rate);
    out.saturated[i] = out.strain_rate[i] != wanted;
  }
  return out;
}

}  // namespace vt::control
