#include "virtual_triaxial/dem/periodic_cell.h"

namespace vt::dem {

PeriodicCell::PeriodicCell(const Vec3& lengths)
    : h_(Mat3::diagonal(lengths)), h_ref_(Mat3::diagonal(lengths)) {
  update_inverse();
}

PeriodicCell::PeriodicCell(const Mat3& h, const Mat3& h_reference) : h_(h), h_ref_(h_reference) {
  update_inverse();
}

void PeriodicCell::deform(double dt) {
  // (I + L dt) H. Written out so that a diagonal L touches each row once.
  Mat3 f = Mat3::identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) f.m[i][j] += l_.m[i][j] * dt;
  h_ = f * h_;
  update_inverse();
}

Vec3 PeriodicCell::heights() const {
  const Vec3 a = h_.column(0), b = h_.column(1), c = h_.column(2);
  const double v = volume();
  return {v / norm(cross(b, c)), v / norm(cross(c, a)), v / norm(cross(a, b))};
}

Vec3 PeriodicCell::log_strain() const {
  Vec3 e;
  for (int i = 0; i < 3; ++i) e[i] = std::log(norm(h_.column(i)) / norm(h_ref_.column(i)));
  return e;
}

double PeriodicCell::log_volume_strain() const {
  return std::log(std::fabs(determinant(h_)) / std::fabs(determinant(h_ref_)));
}

}  // namespace vt::dem
