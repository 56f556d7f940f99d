#include "virtual_triaxial/dem/rigid_rotation.h"

#include <cmath>

namespace vt::dem {

double rotational_energy(const Quaternion& q, const Vec3& l, const Vec3& inertia) {
  const Vec3 lb = q.rotate_inverse(l);
  return 0.5 * (lb.x * lb.x / inertia.x + lb.y * lb.y / inertia.y + lb.z * lb.z / inertia.z);
}

namespace {

/// Exact free motion of a body with I2 == I3 (symmetry axis body x).
Quaternion free_symmetric(const Quaternion& q, const Vec3& l, const Vec3& inertia, double h) {
  const double lmag = norm(l);
  if (!(lmag > 0.0)) return q;
  const Vec3 lhat = (1.0 / lmag) * l;
  const double precession = lmag * h / inertia.y;  // |L| h / I_perp [rad]
  const Vec3 e = q.rotate(Vec3{1.0, 0.0, 0.0});
  // spin about the body axis: (L.e)(1/I1 - 1/I2) h = (L.e) h (I2 - I1)/(I1 I2)
  const double spin = dot(l, e) * h * (inertia.y - inertia.x) / (inertia.x * inertia.y);
  const Quaternion qp = axis_angle(lhat, precession);
  const Quaternion qs = axis_angle(Vec3{1.0, 0.0, 0.0}, spin);
  return normalized(qp * q * qs);
}

/// Exact flow of T_k = pi_k^2 / (2 I_k) for time h: rotate the body about its
/// axis k by phi = pi_k h / I_k; the body-frame momentum turns by -phi.
void axis_flow(Quaternion& q, Vec3& pi, const Vec3& inertia, int k, double h) {
  const double phi = pi[k] * h / inertia[k];
  Vec3 u;
  u[k] = 1.0;
  q = q * axis_angle(u, phi);
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const double c = std::cos(phi), s = std::sin(phi);
  const double pi_i = pi[i], pi_j = pi[j];
  pi[i] = c * pi_i + s * pi_j;
  pi[j] = -s * pi_i + c * pi_j;
}

Quaternion free_split(const Quaternion& q0, const Vec3& l, const Vec3& inertia, double h) {
  Quaternion q = q0;
  Vec3 pi = q.rotate_inverse(l);
  const double hh = 0.5 * h;
  axis_flow(q, pi, inertia, 0, hh);
  axis_flow(q, pi, inertia, 1, hh);
  axis_flow(q, pi, inertia, 2, h);
  axis_flow(q, pi, inertia, 1, hh);
  axis_flow(q, pi, inertia, 0, hh);
  return normalized(q);
}

/// free_rotation (a local function, so advance_rotation can inline it).
Quaternion free_motion(const Quaternion& q, const Vec3& l, const Vec3& inertia, double h) {
  if (inertia.y == inertia.z) return free_symmetric(q, l, inertia, h);
  return free_split(q, l, inertia, h);
}

}  // namespace

Quaternion free_rotation(const Quaternion& q, const Vec3& l, const Vec3& inertia, double h) {
  return free_motion(q, l, inertia, h);
}

void advance_rotation(Quaternion& q, Vec3& l, const Vec3& torque, const Vec3& inertia,
                      double alpha, double dt) {
  const double half = 0.5 * alpha * dt;
  const double decay = (1.0 - half) / (1.0 + half);
  const double kick = dt / (1.0 + half);
  l = decay * l + kick * torque;
  q = free_motion(q, l, inertia, dt);
}

void advance_rotation_omega(Quaternion& q, Vec3& w, const Vec3& torque, const Vec3& inertia,
                            double alpha, double dt) {
  if (inertia.y == inertia.z) {  // the same step as advance_rotation, without frame rotations
    advance_symmetric_rotation(q, w, torque, inertia, SymmetricStepConstants::of(inertia, alpha, dt));
    return;
  }
  Vec3 l = angular_momentum_world(q, w, inertia);
  advance_rotation(q, l, torque, inertia, alpha, dt);
  w = angular_velocity_world(q, l, inertia);
}

}  // namespace vt::dem
