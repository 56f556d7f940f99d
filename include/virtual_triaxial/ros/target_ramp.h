// Per-axis linear ramp of servo stress targets in SIMULATION time, for
// servo_controller_node's set_confining_pressure / set_axis_targets.
//
// Each axis i ramps linearly from the value it had when the ramp was set to
// its new target over `duration` seconds of simulation time (0 = a step).
// Values [Pa], compression positive. ROS-free.
#pragma once

#include <array>

#include "virtual_triaxial/dem/vec3.h"

namespace vt::ros {

class TargetRamp {
 public:
  /// All axes at `targets` from now on (no ramp).
  void reset(const dem::Vec3& targets);
  /// Axis `axis` ramps from value(time) to `target` over `duration` >= 0 [s]
  /// starting at simulation time `time` [s].
  void ramp(int axis, double target, double time, double duration);
  /// Targets at simulation time `time` [s].
  dem::Vec3 value(double time) const;
  /// Final targets (after every ramp).
  dem::Vec3 final_targets() const;

 private:
  struct Axis {
    double from = 0.0, to = 0.0, start = 0.0, duration = 0.0;
  };
  static double at(const Axis& a, double time);
  std::array<Axis, 3> axes_{};
};

}  // namespace vt::ros
