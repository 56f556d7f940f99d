// TargetRamp: linear per-axis target ramps in simulation time. See target_ramp.h.
#include "virtual_triaxial/ros/target_ramp.h"

#include <stdexcept>

namespace vt::ros {

void TargetRamp::reset(const dem::Vec3& targets) {
  for (int i = 0; i < 3; ++i) axes_[static_cast<std::size_t>(i)] = Axis{targets[i], targets[i], 0.0, 0.0};
}

double TargetRamp::at(const Axis& a, double time) {
  if (a.duration <= 0.0 || time >= a.start + a.duration) return a.to;
  if (time <= a.start) return a.from;
  return a.from + (a.to - a.from) * ((time - a.start) / a.duration);
}

void TargetRamp::ramp(int axis, double target, double time, double duration) {
  if (axis < 0 || axis > 2) throw std::out_of_range("TargetRamp: axis not in 0..2");
  Axis& a = axes_[static_cast<std::size_t>(axis)];
  a = Axis{at(a, time), target, time, duration > 0.0 ? duration : 0.0};
}

dem::Vec3 TargetRamp::value(double time) const {
  return {at(axes_[0], time), at(axes_[1], time), at(axes_[2], time)};
}

dem::Vec3 TargetRamp::final_targets() const { return {axes_[0].to, axes_[1].to, axes_[2].to}; }

}  // namespace vt::ros
