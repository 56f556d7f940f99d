#include "virtual_triaxial/dem/spheroid.h"

#include <cmath>

namespace vt::dem {

double Spheroid::volume() const { return 4.0 / 3.0 * M_PI * a * b * b; }

double Spheroid::nominal_radius() const { return std::cbrt(a * b * b); }

double Spheroid::average_radius() const { return (a + 2.0 * b) / 3.0; }

double Spheroid::mass(double density) const { return density * volume(); }

Vec3 Spheroid::principal_inertia(double density) const {
  const double m = mass(density);
  const double i_axis = 0.4 * m * b * b;          // 2/5 m b^2
  const double i_perp = 0.2 * m * (a * a + b * b);  // 1/5 m (a^2 + b^2)
  return {i_axis, i_perp, i_perp};
}

Mat3 Spheroid::shape_matrix() const {
  const Vec3 e = axis();
  const double ib2 = 1.0 / (b * b);
  const double k = 1.0 / (a * a) - ib2;
  Mat3 r = k * outer(e, e);
  for (int i = 0; i < 3; ++i) r.m[i][i] += ib2;
  return r;
}

Mat3 Spheroid::inverse_shape_matrix() const {
  const Vec3 e = axis();
  const double b2 = b * b;
  Mat3 r = (a * a - b2) * outer(e, e);
  for (int i = 0; i < 3; ++i) r.m[i][i] += b2;
  return r;
}

double Spheroid::support(const Vec3& n) const {
  const double c = dot(axis(), n);
  const double b2 = b * b;
  return std::sqrt(b2 + (a * a - b2) * c * c);
}

Vec3 Spheroid::support_point(const Vec3& n) const {
  const Vec3 e = axis();
  const double c = dot(e, n);
  const double b2 = b * b;
  const double k = a * a - b2;
  const double h = std::sqrt(b2 + k * c * c);
  return (1.0 / h) * (b2 * n + (k * c) * e);
}

double Spheroid::level(const Vec3& x) const {
  const double c = dot(axis(), x);
  const double b2 = b * b;
  // x^T A x = |x|^2 / b^2 + (1/a^2 - 1/b^2) c^2
  return (norm2(x) - c * c) / b2 + c * c / (a * a);
}

}  // namespace vt::dem
