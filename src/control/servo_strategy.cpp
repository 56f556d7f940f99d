// ServoStrategy base (targets, mask, tolerance check), parameter validation
// and the strategy factory. See servo_strategy.h.
#include "virtual_triaxial/control/servo_strategy.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "virtual_triaxial/control/pid_servo.h"
#include "virtual_triaxial/control/proportional_servo.h"

namespace vt::control {

namespace {
const char* const kAxisName[3] = {"x", "y", "z"};
}  // namespace

double stiffness_normalised_rate(double u, double k, double dt, double cap) {
  if (u == 0.0) return 0.0;
  if (k > 0.0 && std::abs(u) < k * dt * cap) return -u / (k * dt);
  return u > 0.0 ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
}

bool AxisMask::operator[](int i) const {
  switch (i) {
    case 0: return x;
    case 1: return y;
    case 2: return z;
    default: throw std::out_of_range("AxisMask: axis index " + std::to_string(i) + " not in 0..2");
  }
}

void validate_servo_parameters(const ServoParameters& p) {
  if (!(std::isfinite(p.gain) && p.gain > 0.0 && p.gain <= 1.0))
    throw std::invalid_argument("ServoParameters: gain must be in (0, 1], got " +
                                std::to_string(p.gain));
  if (!(std::isfinite(p.max_strain_rate) && p.max_strain_rate > 0.0))
    throw std::invalid_argument(
        "ServoParameters: max_strain_rate [1/s] must be finite and > 0, got " +
        std::to_string(p.max_strain_rate));
  if (!(std::isfinite(p.ki) && p.ki >= 0.0 && p.ki <= 1.0))
    throw std::invalid_argument("ServoParameters: ki must be in [0, 1], got " + std::to_string(p.ki));
  if (!(std::isfinite(p.kd) && p.kd >= 0.0 && p.kd <= 0.2))
    throw std::invalid_argument("ServoParameters: kd must be in [0, 0.2], got " + std::to_string(p.kd));
  if (!(std::isfinite(p.max_rate_change) && p.max_rate_change >= 0.0))
    throw std::invalid_argument(
        "ServoParameters: max_rate_change [1/s] must be finite and >= 0 (0 = no limit), got " +
        std::to_string(p.max_rate_change));
}

void ServoStrategy::restore_memory(const std::vector<double>& m) {
  if (!m.empty())
    throw std::invalid_argument("servo memory: the '" + name() + "' law keeps none, got " + std::to_string(m.size()) +
                                " numbers");
}

void ServoStrategy::store_targets(const dem::Vec3& target_stress) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(target_stress[i]))
      throw std::invalid_argument(std::string("servo '") + name() + "': target_stress." +
                                  kAxisName[i] + " is not finite");
  targets_ = target_stress;
}

void ServoStrategy::require_initialised(const char* what) const {
  if (!initialised_)
    throw std::logic_error(std::string("servo '") + name() + "': " + what +
                           " called before init()");
}

bool ServoStrategy::within(const dem::Vec3& stress, double tol) const {
  require_initialised("within()");
  if (!(std::isfinite(tol) && tol >= 0.0))
    throw std::invalid_argument("servo within(): tol must be finite and >= 0, got " +
                                std::to_string(tol));
  for (int i = 0; i < 3; ++i) {
    if (!axes_[i]) continue;
    // written so that a NaN stress compares false
    if (!(std::abs(stress[i] - targets_[i]) <= tol * std::abs(targets_[i]))) return false;
  }
  return true;
}

std::unique_ptr<ServoStrategy> make_servo(const std::string& name, const ServoParameters& p) {
  if (name == "proportional") return std::make_unique<ProportionalServo>(p);
  if (name == "pid") return std::make_unique<PidServo>(p);
  throw std::invalid_argument("make_servo: unknown servo strategy '" + name +
                              "' (known: proportional, pid)");
}

}  // namespace vt::control
