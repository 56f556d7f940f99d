#include "virtual_triaxial/dem/particles.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "virtual_triaxial/dem/spheroid.h"

namespace vt::dem {

double sphere_volume(double r) { return 4.0 / 3.0 * M_PI * r * r * r; }

void Particles::resize(std::size_t n) {
  id.resize(n);
  shape.resize(n, Shape::Sphere);
  radius.resize(n);
  semi_axes.resize(n);
  mass.resize(n);
  inertia.resize(n);
  frac.resize(n);
  velocity.resize(n);
  omega.resize(n);
  orientation.resize(n);
  material.resize(n, 0);
}

void Particles::reserve(std::size_t n) {
  id.reserve(n); shape.reserve(n); radius.reserve(n); semi_axes.reserve(n);
  mass.reserve(n); inertia.reserve(n); frac.reserve(n); velocity.reserve(n);
  omega.reserve(n); orientation.reserve(n); material.reserve(n);
}

void Particles::add_sphere(std::int64_t pid, double r, double rho, const Vec3& s,
                           const Vec3& v, const Vec3& w, std::int32_t mat) {
  const double m = rho * sphere_volume(r);
  const double i = 0.4 * m * r * r;  // solid sphere: 2/5 m R^2
  id.push_back(pid);
  shape.push_back(Shape::Sphere);
  radius.push_back(r);
  semi_axes.push_back({r, r, r});
  mass.push_back(m);
  inertia.push_back({i, i, i});
  frac.push_back(s);
  velocity.push_back(v);
  omega.push_back(w);
  orientation.push_back({});
  material.push_back(mat);
}

void Particles::add_spheroid(std::int64_t pid, double a, double b, double rho, const Vec3& s,
                             const Quaternion& q, const Vec3& v, const Vec3& w, std::int32_t mat) {
  if (!(b > 0.0 && a >= b && std::isfinite(a)))
    throw std::invalid_argument("spheroid semi-axes: need a >= b > 0 (prolate, symmetry axis a)");
  if (!(rho > 0.0)) throw std::invalid_argument("spheroid density: must be > 0");
  const Spheroid sp(a, b, q);
  id.push_back(pid);
  shape.push_back(Shape::Spheroid);
  radius.push_back(sp.nominal_radius());
  semi_axes.push_back({a, b, b});
  mass.push_back(sp.mass(rho));
  inertia.push_back(sp.principal_inertia(rho));
  frac.push_back(s);
  velocity.push_back(v);
  omega.push_back(w);
  orientation.push_back(q);
  material.push_back(mat);
}

bool Particles::has_spheroids() const {
  return std::any_of(shape.begin(), shape.end(), [](Shape s) { return s == Shape::Spheroid; });
}

double Particles::min_minor_semi_axis() const {
  double r = INFINITY;
  for (const Vec3& a : semi_axes) r = std::min(r, a.y);
  return r;
}

double Particles::max_bounding_radius() const {
  double r = 0.0;
  for (const Vec3& a : semi_axes) r = std::max(r, a.x);
  return r;
}

double Particles::solid_volume() const {
  double v = 0.0;
  for (const Vec3& a : semi_axes) v += 4.0 / 3.0 * M_PI * a.x * a.y * a.z;
  return v;
}

}  // namespace vt::dem
