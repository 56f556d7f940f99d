// Periodic cell with homogeneous deformation (appendix 5).
//
// The cell is the parallelepiped spanned by the columns of H [m]; a particle at
// fractional coordinates s sits at x = H s. Each step the cell deforms with
// the velocity gradient L [1/s]:  H <- (I + L dt) H,  which is eq. 131
// applied to every position (x = X + (I + eps_dot dt) x_old, with X the
// particle's own displacement). Internally L uses the mechanics sign
// convention (extension positive); conversion to the geomechanics convention
// (compression positive) happens once, in the measures.
//
// Only the normal components of L are driven today (per-axis strain rates);
// H and L are full 3x3 so that shear components can be added later without
// touching the contact code, which only sees branch vectors H * ds.
#pragma once

#include <cmath>

#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

class PeriodicCell {
 public:
  PeriodicCell() = default;
  /// Orthogonal cell with edge lengths (lx, ly, lz) [m]; also the strain reference.
  explicit PeriodicCell(const Vec3& lengths);
  PeriodicCell(const Mat3& h, const Mat3& h_reference);

  const Mat3& h() const { return h_; }
  const Mat3& h_inverse() const { return h_inv_; }
  const Mat3& h_reference() const { return h_ref_; }
  const Mat3& velocity_gradient() const { return l_; }
  double volume() const { return std::fabs(determinant(h_)); }

  /// Velocity gradient L [1/s], extension positive.
  void set_velocity_gradient(const Mat3& l) { l_ = l; }
  /// Diagonal L from per-axis strain rates [1/s], extension positive.
  void set_strain_rates(const Vec3& rates) { l_ = Mat3::diagonal(rates); }
  Vec3 strain_rates() const { return {l_.m[0][0], l_.m[1][1], l_.m[2][2]}; }

  /// H <- (I + L dt) H (eq. 131).
  void deform(double dt);
  /// Reset the strain reference to the current shape.
  void reset_reference() { h_ref_ = h_; }

  /// Minimum image of a fractional difference: each component in [-1/2, 1/2].
  static Vec3 minimum_image(Vec3 ds) {
    ds.x -= std::nearbyint(ds.x);
    ds.y -= std::nearbyint(ds.y);
    ds.z -= std::nearbyint(ds.z);
    return ds;
  }
  /// Minimum-image branch vector from fractional position a to b [m].
  Vec3 branch(const Vec3& sa, const Vec3& sb) const { return h_ * minimum_image(sb - sa); }
  Vec3 to_cartesian(const Vec3& s) const { return h_ * s; }
  Vec3 to_fractional(const Vec3& x) const { return h_inv_ * x; }
  /// Map s into [0,1)^3 (exact: subtracts integers).
  static Vec3 wrap(Vec3 s) {
    s.x -= std::floor(s.x);
    s.y -= std::floor(s.y);
    s.z -= std::floor(s.z);
    // floor(-tiny) = -1 gives 1.0 after subtraction in rounding; fold it back.
    if (s.x >= 1.0) s.x -= 1.0;
    if (s.y >= 1.0) s.y -= 1.0;
    if (s.z >= 1.0) s.z -= 1.0;
    return s;
  }
  /// Distances between opposite faces [m] (cell heights), for binning.
  Vec3 heights() const;
  /// Logarithmic strain of the cell edges, ln(|h_i| / |h_ref,i|), extension positive.
  Vec3 log_strain() const;
  /// Volumetric log strain ln(V / V_ref), extension positive.
  double log_volume_strain() const;

 private:
  void update_inverse() { h_inv_ = inverse(h_); }

  Mat3 h_ = Mat3::identity();
  Mat3 h_inv_ = Mat3::identity();
  Mat3 h_ref_ = Mat3::identity();
  Mat3 l_{};
};

}  // namespace vt::dem
