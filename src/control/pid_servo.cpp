// Stiffness-normalised PID servo with anti-windup and a rate limit; the law,
// its units and its closed-loop properties are in pid_servo.h.
#include "virtual_triaxial/control/pid_servo.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace vt::control {

namespace {

const char* const kAxisName[3] = {"x", "y", "z"};

/// Rate applied on one axis and how it relates to the rate the law wants.
struct AxisRate {
  double rate = 0.0;       ///< applied [1/s]
  bool saturated = false;  ///< applied != wanted (cap or rate limit)
  int beyond = 0;          ///< sign(wanted - applied): where the law wants to go further
};

}  // namespace

PidServo::PidServo(const ServoParameters& p) : p_(p) { validate_servo_parameters(p_); }

void PidServo::reset_state() {
  integral_ = {};
  prev_error_ = {};
  prev_rate_ = {};
  has_prev_ = false;
}

void PidServo::init(const dem::Vec3& target_stress, const AxisMask& axes) {
  store_targets(target_stress);
  axes_ = axes;
  initialised_ = true;
  running_ = false;
  reset_state();
}

void PidServo::set_targets(const dem::Vec3& target_stress) {
  require_initialised("set_targets()");
  store_targets(target_stress);
}

std::vector<double> PidServo::memory() const {
  std::vector<double> m;
  for (const dem::Vec3* v : {&integral_, &prev_error_, &prev_rate_})
    for (int i = 0; i < 3; ++i) m.push_back((*v)[i]);
  m.push_back(has_prev_ ? 1.0 : 0.0);
  return m;
}

void PidServo::restore_memory(const std::vector<double>& m) {
  if (m.size() != 10)
    throw std::invalid_argument("servo memory: the 'pid' law keeps 10 numbers, got " + std::to_string(m.size()));
  std::size_t k = 0;
  for (dem::Vec3* v : {&integral_, &prev_error_, &prev_rate_})
    for (int i = 0; i < 3; ++i) (*v)[i] = m[k++];
  has_prev_ = m[9] != 0.0;
}

void PidServo::start(double /*time*/) {
  require_initialised("start()");
  reset_state();
  running_ = true;
}

void PidServo::stop() { running_ = false; }

void PidServo::set_parameters(const ServoParameters& p) {
  validate_servo_parameters(p);
  p_ = p;
  if (p_.ki == 0.0) integral_ = {};
}

ServoOutput PidServo::update(const ServoInput& in) {
  if (!running_) throw std::logic_error("servo 'pid': update() called while not started");
  if (!(std::isfinite(in.dt) && in.dt > 0.0))
    throw std::invalid_argument("servo 'pid': dt must be finite and > 0, got " + std::to_string(in.dt));
  for (int i = 0; i < 3; ++i)
    if (axes_[i] && (!std::isfinite(in.stress[i]) || !std::isfinite(in.stiffness[i])))
      throw std::invalid_argument(std::string("servo 'pid': stress/stiffness.") + kAxisName[i] +
                                  " is not finite");

  const double cap = p_.max_strain_rate;
  ServoOutput out;
  for (int i = 0; i < 3; ++i) {
    if (!axes_[i]) continue;  // rate, error 0; not saturated; no state
    const double e = in.stress[i] - targets_[i];
    const double de = has_prev_ ? e - prev_error_[i] : 0.0;
    const double k = in.stiffness[i];
    const double prev_rate = prev_rate_[i];

    // The law for a given integral term s [Pa].
    auto law = [&](double s) {
      const double wanted = stiffness_normalised_rate(p_.gain * e + s + p_.kd * de, k, in.dt, cap);
      AxisRate r;
      r.rate = std::clamp(wanted, -cap, cap);
      if (p_.max_rate_change > 0.0)
        r.rate = std::clamp(r.rate, prev_rate - p_.max_rate_change, prev_rate + p_.max_rate_change);
      r.rate = std::clamp(r.rate, -cap, cap);  // the cap has priority (a lowered cap)
      r.saturated = r.rate != wanted;
      r.beyond = !r.saturated ? 0 : (wanted > r.rate ? 1 : -1);
      return r;
    };

    double s = integral_[i] + p_.ki * e;
    AxisRate r = law(s);
    // Conditional integration: the step ki e moves the wanted rate by
    // -ki e / (K dt), i.e. in direction -sign(e); if that deepens the
    // saturation, keep the old integral.
    if (r.saturated && p_.ki > 0.0 && e * r.beyond < 0.0) {
      s = integral_[i];
      r = law(s);
    }
    integral_[i] = s;
    prev_error_[i] = e;
    prev_rate_[i] = r.rate;
    out.error[i] = e;
    out.strain_rate[i] = r.rate;
    out.saturated[i] = r.saturated;
  }
  has_prev_ = true;
  return out;
}

}  // namespace vt::control
