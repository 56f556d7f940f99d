// Spheroid geometry and mass properties (chapter 4 of the dissertation).
//
// A spheroid is an ellipsoid with semi-axes a, b, b: the symmetry axis is the
// body x axis (semi-axis a), the two minor semi-axes are equal (b). The
// dissertation uses prolate spheroids, a >= b (aspect ratio a/b ~ 1.2); every
// formula below also holds for a < b (oblate), only the bounding radius picks
// max(a, b). Orientation q: unit quaternion, body -> world (quaternion.h).
//
// Formulas (SI: lengths m, density kg/m^3, mass kg, inertia kg m^2):
//   volume                V = 4/3 pi a b^2
//   nominal radius        R_nom = cbrt(a b^2)      (equal-volume sphere; the
//                         radius used by the ND damping model, eq. 63)
//   average radius        R_avg = (a + 2 b) / 3    (eq. 104 "average radius":
//                         the arithmetic mean of the three semi-axes a, b, b.
//                         Chosen because it is the plain reading of "average",
//                         it is what the Hertz law of appendix 3 takes as R_i,
//                         and it reduces to R for a sphere. A curvature-based
//                         radius is not used.)
//   bounding radius       max(a, b) (radius of the circumscribed sphere)
//   mass                  m = rho V
//   principal inertia     I_xx = 2/5 m b^2          (about the symmetry axis)
//   (body frame)          I_yy = I_zz = 1/5 m (a^2 + b^2)
//   symmetry axis (world) e = q (1,0,0)
//   shape matrix          A = R diag(1/a^2, 1/b^2, 1/b^2) R^T
//                           = I / b^2 + (1/a^2 - 1/b^2) e e^T   [1/m^2]
//                         surface: x^T A x = 1 (x relative to the centre)
//   inverse shape matrix  A^-1 = b^2 I + (a^2 - b^2) e e^T      [m^2]
//   support function      h(n) = max_{x in E} n.x = sqrt(n^T A^-1 n)  [m], |n| = 1
//                              = sqrt(b^2 + (a^2 - b^2) (e.n)^2)
//   support point         p(n) = A^-1 n / h(n)   [m]: the surface point whose
//                         outward normal is n (relative to the centre)
//
// Every length-valued result is computed from products/sums of lengths and
// square roots of squared lengths, so it scales exactly under power-of-two
// changes of the length unit (DESIGN §3). The cube root of R_nom is exact for
// factors 2^(3k) of a b^2, i.e. for length factors 2^k.
// Cost: every function is O(1), a few tens of flops.
#pragma once

#include "virtual_triaxial/dem/quaternion.h"
#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

struct Spheroid {
  double a = 0.0;  ///< semi-axis along the body x (symmetry) axis [m]
  double b = 0.0;  ///< the two equal semi-axes (body y, z) [m]
  Quaternion q;    ///< orientation, body -> world

  Spheroid() = default;
  Spheroid(double a_, double b_, const Quaternion& q_ = {}) : a(a_), b(b_), q(q_) {}
  /// From the (a, b, b) triple stored in Particles::semi_axes.
  static Spheroid from_semi_axes(const Vec3& semi_axes, const Quaternion& q_ = {}) {
    return Spheroid(semi_axes.x, semi_axes.y, q_);
  }

  double volume() const;          ///< 4/3 pi a b^2 [m^3]
  double nominal_radius() const;  ///< cbrt(a b^2) [m]
  double average_radius() const;  ///< (a + 2b)/3 [m], R_i of eq. 104
  double bounding_radius() const { return a > b ? a : b; }  ///< [m]
  double minor_semi_axis() const { return a < b ? a : b; }  ///< [m]
  double mass(double density) const;             ///< rho V [kg]
  Vec3 principal_inertia(double density) const;  ///< body (I_xx, I_yy, I_zz) [kg m^2]

  /// World-frame symmetry axis e = q (1, 0, 0) (unit).
  Vec3 axis() const { return q.rotate(Vec3{1.0, 0.0, 0.0}); }
  Mat3 shape_matrix() const;          ///< A [1/m^2]
  Mat3 inverse_shape_matrix() const;  ///< A^-1 [m^2]
  /// h(n) for a unit world direction n [m].
  double support(const Vec3& n) const;
  /// p(n) = A^-1 n / h(n) for a unit world direction n [m], relative to the centre.
  Vec3 support_point(const Vec3& n) const;
  /// x^T A x for x relative to the centre [-]: < 1 inside, 1 on the surface.
  double level(const Vec3& x) const;
};

}  // namespace vt::dem
