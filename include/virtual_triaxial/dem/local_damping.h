// Cundall's local non-viscous damping (Cundall 1987; the `local damping` of
// PFC and the `damping` of YADE's NewtonIntegrator).
//
// Each component k of the resultant force F on a particle (and of the
// resultant moment M) is reduced against the particle's motion:
//     F_k,d = F_k - a |F_k| sign(v_k),     M_k,d = M_k - a |M_k| sign(w_k),
// with a in [0, 1) the damping coefficient [1] and v, w the fluctuating
// (non-affine) velocity and the angular velocity at the force's time,
// estimated as in YADE: v(t) = v(t - dt/2) + dt/2 F/m (w likewise with M/I).
// The damping force is proportional to the out-of-balance force, not to the
// velocity: it vanishes in equilibrium and leaves steady motion (F = 0)
// untouched, unlike mass damping (mass_damping.h), and it is the same
// fraction for every particle size.
//
// Closed form on a single linear oscillator (m x'' = -k x): on a stretch
// moving away from x = 0 the force is scaled by (1 + a), on one moving back
// by (1 - a), so energy conservation on each stretch gives the amplitude
// ratio per full cycle
//     A_(n+1) / A_n = (1 - a) / (1 + a),
// (the speed at x = 0 by sqrt((1 - a)/(1 + a)) per half cycle), independent
// of k, m and the amplitude. For small a the equivalent damping ratio is
// xi = a / pi (log decrement 2a).
// The energy the damping takes in a step is -F_d . v_mid dt (F_d = the
// damping part, v_mid the mid-step velocity), counted as damping in the
// energy budget.
#pragma once

#include <cmath>

#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

class LocalDamping {
 public:
  LocalDamping() = default;
  /// a in [0, 1); throws std::invalid_argument otherwise.
  explicit LocalDamping(double coefficient);

  double coefficient() const { return a_; }

  /// The damped force: F_k - a |F_k| sign(u_k) per component, u the velocity
  /// estimate at the force's time (sign(0) = 0: no damping along a component at rest).
  Vec3 damped(const Vec3& f, const Vec3& u) const {
    return {f.x - a_ * std::fabs(f.x) * sign(u.x), f.y - a_ * std::fabs(f.y) * sign(u.y),
            f.z - a_ * std::fabs(f.z) * sign(u.z)};
  }

 private:
  static double sign(double x) { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); }
  double a_ = 0.0;
};

}  // namespace vt::dem
