// Particle state of the DEM core, structure-of-arrays.
//
// Units (SI): radius m, mass kg, inertia kg m^2, velocity m/s, angular
// velocity rad/s. Positions are stored as fractional cell coordinates
// s in [0,1)^3 (x = H s, see PeriodicCell): the affine part of the cell
// deformation (eq. 131) is then carried by H alone and wrapping is exact.
// `velocity` is the fluctuating (non-affine) velocity: the total velocity of
// a particle at x is L x + velocity, with L the cell's velocity gradient.
//
// Spheroids (chapter 4): shape tag, semi-axes (a >= b = c), body-frame
// principal inertia and an orientation quaternion are stored for every
// particle; spheres use a = b = radius and q = identity. A spheroid's
// `radius` is its nominal (equal-volume) radius cbrt(a b^2) (spheroid.h),
// used by the ND damping (eq. 63); its inertia is the body-frame principal
// inertia (I_axis, I_perp, I_perp), I_axis = 2/5 m b^2, I_perp = 1/5 m (a^2 + b^2).
// For a spheroid `omega` is the world angular velocity at half steps; the
// rigid-rotation integrator derives the angular momentum from it and q.
#pragma once

#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/quaternion.h"
#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

enum class Shape : std::uint8_t { Sphere = 0, Spheroid = 1 };

struct Particles {
  std::vector<std::int64_t> id;      ///< stable id, unique, keys contact history
  std::vector<Shape> shape;
  std::vector<double> radius;        ///< nominal (equal-volume) radius [m]
  std::vector<Vec3> semi_axes;       ///< (a, b, b) [m]; spheres: (R, R, R)
  std::vector<double> mass;          ///< [kg]
  std::vector<Vec3> inertia;         ///< principal moments, body frame [kg m^2]
  std::vector<Vec3> frac;            ///< fractional position s in [0,1)^3
  std::vector<Vec3> velocity;        ///< fluctuating velocity [m/s]
  std::vector<Vec3> omega;           ///< angular velocity, world frame [rad/s]
  std::vector<Quaternion> orientation;  ///< body -> world rotation
  std::vector<std::int32_t> material;   ///< index into the material table

  std::size_t size() const { return id.size(); }
  void resize(std::size_t n);
  void reserve(std::size_t n);
  /// Append a sphere of radius r and density rho at fractional position s.
  void add_sphere(std::int64_t pid, double r, double rho, const Vec3& s,
                  const Vec3& v = {}, const Vec3& w = {}, std::int32_t mat = 0);
  /// Append a prolate spheroid with semi-axes a >= b (symmetry axis = body x)
  /// and density rho at fractional position s; q: unit quaternion body ->
  /// world. Nominal radius cbrt(a b^2), inertia from spheroid.h. A spheroid
  /// with a == b is still a spheroid (it goes through the spheroid code).
  /// Throws std::invalid_argument unless a >= b > 0 and rho > 0.
  void add_spheroid(std::int64_t pid, double a, double b, double rho, const Vec3& s,
                    const Quaternion& q = {}, const Vec3& v = {}, const Vec3& w = {},
                    std::int32_t mat = 0);
  /// True when any particle is a spheroid (O(N) scan: cache the answer).
  bool has_spheroids() const;
  /// Smallest minor semi-axis (= smallest radius for spheres) [m].
  double min_minor_semi_axis() const;
  /// Largest bounding radius (major semi-axis) [m].
  double max_bounding_radius() const;
  /// Sum of particle volumes [m^3].
  double solid_volume() const;
};

/// Volume of a sphere of radius r.
double sphere_volume(double r);

}  // namespace vt::dem
