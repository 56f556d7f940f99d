#include "virtual_triaxial/dem/time_scale.h"

#include <cmath>

namespace vt::dem {

TimeScale TimeScale::from(double min_minor_semi_axis, double density, double young, double ct) {
  TimeScale t;
  t.l0 = 2.0 * min_minor_semi_axis;              // eq. 15
  t.t0 = t.l0 * std::sqrt(density / young);      // eq. 16 / 91
  t.ct = ct;
  t.dt = ct * t.t0;                              // eq. 132
  return t;
}

}  // namespace vt::dem
