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

SymmetricRotationStep advance_symmetric_rotation(Quaternion& q, Vec3& w, const Vec3& torque,
                                                 const Vec3& inertia, const SymmetricStepConstants& k) {
  const double i1 = inertia.x, i2 = inertia.y;
  const double inv_diff = k.inv_i1 - k.inv_i2;  // 1/I1 - 1/I2 [1/(kg m^2)]
  const Vec3 e_old = body_x_axis(q);
  SymmetricRotationStep out;
  out.l_old = i2 * w + ((i1 - i2) * dot(e_old, w)) * e_old;
  const Vec3 l = k.decay * out.l_old + k.kick * torque;
  out.l_new = l;
  // Exact torque-free drift (as free_symmetric, with e known).
  const double l2 = norm2(l);
  if (l2 > 0.0) {
    const double lmag = std::sqrt(l2);
    double cp, sp, cs, ss;
    cos_sin(0.5 * lmag * k.dt_inv_i2, cp, sp);  // precession |L| dt / I2 about L^
    cos_sin(0.5 * dot(l, e_old) * k.dt * inv_diff, cs, ss);  // spin about the body axis
    // Q(L^, precession) q Q(x, spin), the spin factor (cs, ss, 0, 0) written out
    const Quaternion qs{q.w * cs - q.x * ss, q.w * ss + q.x * cs, q.y * cs + q.z * ss, q.z * cs - q.y * ss};
    const Vec3 u = (sp / lmag) * l;
    const Quaternion r = Quaternion{cp, u.x, u.y, u.z} * qs;
    // |r| = 1 to rounding: one Newton step for 1/|r| (exact to O((|r|^2 - 1)^2))
    // instead of a square root and a division.
    const double f = 1.5 - 0.5 * (r.w * r.w + r.x * r.x + r.y * r.y + r.z * r.z);
    q = {f * r.w, f * r.x, f * r.y, f * r.z};
  }
  const Vec3 e_new = body_x_axis(q);
  w = k.inv_i2 * l + (inv_diff * dot(e_new, l)) * e_new;
  const Vec3 l_mid = 0.5 * (out.l_old + l);
  const double el = dot(e_old, l_mid);
  out.two_e_rot = k.inv_i2 * norm2(l_mid) + inv_diff * el * el;
  return out;
}

}  // namespace vt::dem
