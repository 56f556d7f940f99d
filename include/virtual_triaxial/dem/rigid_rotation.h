// Rotation of a rigid body with principal inertia (I1, I2, I3) about body
// axes x, y, z: Euler's equations (eq. 43) with mass-proportional rotational
// damping (eq. 27-29), integrated by a leapfrog-compatible splitting.
//
// Equations (world frame; L = R I_body R^T omega the angular momentum,
// R the rotation of q; SI: L kg m^2/s, torque N m, omega rad/s, t s):
//     dL/dt = M - alpha L          (eq. 43 in the world frame; the damping
//                                   moment alpha I omega of eq. 29 is alpha L)
//     dq/dt = 1/2 (0, omega) q,    omega = R I_body^-1 R^T L
// In the body frame the first line is eq. 43:
//     I dw/dt + w x (I w) + alpha I w = M_body.
//
// Method (symplectic splitting, "kick - free rotor drift"): the state is the
// orientation q at full steps t and the world angular momentum L at half steps
// t - dt/2, like positions and velocities in the translational leapfrog.
//   kick (eq. 2 applied to L, M = torque at t):
//     L(t+dt/2) = L(t-dt/2) (1 - a dt/2)/(1 + a dt/2) + dt/(1 + a dt/2) M(t)
//   drift: q(t+dt) = exact torque-free motion for dt with momentum L(t+dt/2).
// The free motion keeps L (world) fixed; it is solved
//   - exactly for a symmetric body I2 == I3 (spheroids: symmetry axis body x;
//     spheres): q(t+h) = Q(L^, |L| h / I2) q(t) Q(x, (L.e)(1/I1 - 1/I2) h),
//     Q(u, phi) the rotation by phi about unit u, e = q x the symmetry axis.
//     The symmetry axis precesses about L at Omega_p = |L| / I2 exactly, and
//     the rotational energy L^T I^-1 L / 2 is conserved exactly;
//   - for I2 != I3 by the symmetric Strang splitting of the free rotor into
//     rotations about the body axes (Dullweber, Leimkuhler & McLachlan 1997,
//     "NO_SQUISH"-type): x(h/2) y(h/2) z(h) y(h/2) x(h/2), each an exact
//     rotation; energy error O(dt^2), bounded (no drift).
// Without torque and damping L is constant bit for bit; with torque the
// scheme is the second-order, time-reversible, symplectic leapfrog for rigid
// bodies. The quaternion is renormalised after every drift.
// Convergence test (tests/unit/test_rigid_rotation.cpp): heavy symmetric top
// against an RK4 reference, error ratio ~4 when dt is halved; free spheroid:
// L conserved to 1e-9 and precession rate to 1e-4 over 1e5 steps; sphere with
// damping decays by exactly (1 - a dt/2)/(1 + a dt/2) per step.
// Cost per step: symmetric body ~80 flops, 2 sqrt, 2 sin/cos pairs (~90 ns
// on the development VM); asymmetric 5 sin/cos pairs (~220 ns); the omega-
// state wrapper adds 4 quaternion rotations (~50 ns). A symmetric body in the
// omega state (every spheroid of the integrator) takes
// advance_symmetric_rotation instead: the same step written with the
// symmetry axis e, with the step angles' sin/cos by polynomials (cos_sin,
// cos_sinc_of_square) and no square root or division, ~45 ns.
//
// State in omega instead of L: advance_rotation_omega() keeps the world
// angular velocity at half steps, converting omega <-> L with the orientation
// q(t) the step starts from / q(t+dt) it ends at. The conversion is a
// bijection for given q, so it is the same integrator (to rounding); the
// stored omega(t+dt/2) is I_world(q(t+dt))^-1 L(t+dt/2). For spheres this is
// identical to the plain leapfrog omega update.
// Scale: only products/quotients of dimensional quantities; angles are
// dimensionless, so results scale exactly under power-of-two unit changes.
#pragma once

#include <cmath>

#include "virtual_triaxial/dem/quaternion.h"
#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

// The small helpers below are inline: the integrator calls them for every
// spheroid and step, and an out-of-line call in the shared library cannot be
// inlined (symbol interposition).

/// q / |q|.
inline Quaternion normalized(const Quaternion& q) {
  const double s = 1.0 / std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {s * q.w, s * q.x, s * q.y, s * q.z};
}

/// Taylor polynomials of cos x and sin(x)/x in x2 = x^2 to x^10 and x^8:
/// for x2 <= 1/256 (|x| <= 1/16) the truncation error is below 1e-19
/// relative, i.e. they are exact to rounding.
constexpr double kSmallAngle2 = 1.0 / 256;
inline double cos_series(double x2) {  // coefficients (-1)^k / (2k)!
  return 1.0 + x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320 + x2 * (-1.0 / 3628800)))));
}
inline double sinc_series_minus_1(double x2) {  // sin(x)/x - 1: coefficients (-1)^k / (2k+1)!
  return x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 + x2 * (1.0 / 362880))));
}

/// c = cos x, s = sin x [x in rad]. For |x| <= 1/16 (the angles of a DEM
/// step are ~1e-4) the Taylor polynomials above, which cost no library call;
/// std::cos and std::sin otherwise.
/// cos_sin by the polynomials alone (exact to rounding for x^2 <= kSmallAngle2).
inline void cos_sin_small(double x, double& c, double& s) {
  const double x2 = x * x;
  s = x + x * sinc_series_minus_1(x2);
  c = cos_series(x2);
}
inline void cos_sin(double x, double& c, double& s) {
  if (x * x <= kSmallAngle2) {
    cos_sin_small(x, c, s);
  } else {
    c = std::cos(x);
    s = std::sin(x);
  }
}

/// c = cos x, sc = sin(x)/x from x2 = x^2 >= 0 [rad^2], without the square
/// root when x2 <= 1/256 (the polynomials above); std::cos, std::sin of
/// sqrt(x2) otherwise. For a rotation by |v| about v^: the quaternion
/// (cos, (sin/|v|) v) needs no |v|.
/// cos_sinc_of_square by the polynomials alone (exact to rounding for x2 <= kSmallAngle2).
inline void cos_sinc_of_square_small(double x2, double& c, double& sc) {
  sc = 1.0 + sinc_series_minus_1(x2);
  c = cos_series(x2);
}
inline void cos_sinc_of_square(double x2, double& c, double& sc) {
  if (x2 <= kSmallAngle2) {
    cos_sinc_of_square_small(x2, c, sc);
  } else {
    const double x = std::sqrt(x2);
    c = std::cos(x);
    sc = std::sin(x) / x;
  }
}

/// Rotation by angle phi [rad] about the unit axis u (as a unit quaternion).
inline Quaternion axis_angle(const Vec3& u, double phi) {
  double c, s;
  cos_sin(0.5 * phi, c, s);
  return {c, s * u.x, s * u.y, s * u.z};
}

/// World direction of the body x axis, q (1, 0, 0) (the first column of the
/// rotation matrix of q; a spheroid's symmetry axis).
inline Vec3 body_x_axis(const Quaternion& q) {
  return {1.0 - 2.0 * (q.y * q.y + q.z * q.z), 2.0 * (q.x * q.y + q.w * q.z), 2.0 * (q.x * q.z - q.w * q.y)};
}

/// omega = R I^-1 R^T L [rad/s] for world L [kg m^2/s].
inline Vec3 angular_velocity_world(const Quaternion& q, const Vec3& angular_momentum_world,
                                   const Vec3& inertia_body) {
  const Vec3 lb = q.rotate_inverse(angular_momentum_world);
  return q.rotate(Vec3{lb.x / inertia_body.x, lb.y / inertia_body.y, lb.z / inertia_body.z});
}

/// L = R I R^T omega [kg m^2/s] for world omega [rad/s].
inline Vec3 angular_momentum_world(const Quaternion& q, const Vec3& omega_world,
                                   const Vec3& inertia_body) {
  const Vec3 wb = q.rotate_inverse(omega_world);
  return q.rotate(Vec3{wb.x * inertia_body.x, wb.y * inertia_body.y, wb.z * inertia_body.z});
}

/// Rotational kinetic energy L . omega / 2 [J].
double rotational_energy(const Quaternion& q, const Vec3& angular_momentum_world,
                         const Vec3& inertia_body);

/// Torque-free motion of the orientation over time h [s] with world angular
/// momentum L (constant during it). Exact when inertia_body.y == inertia_body.z.
Quaternion free_rotation(const Quaternion& q, const Vec3& angular_momentum_world,
                         const Vec3& inertia_body, double h);

/// One leapfrog step: L(t-dt/2) -> L(t+dt/2) with torque M(t) and damping
/// alpha [1/s] (eq. 2), then q(t) -> q(t+dt).
void advance_rotation(Quaternion& q, Vec3& angular_momentum_world_half, const Vec3& torque_world,
                      const Vec3& inertia_body, double alpha, double dt);

/// Same step with the world angular velocity at half steps as the state
/// (a symmetric body takes advance_symmetric_rotation, as the integrator does).
void advance_rotation_omega(Quaternion& q, Vec3& omega_world_half, const Vec3& torque_world,
                            const Vec3& inertia_body, double alpha, double dt);

/// What advance_symmetric_rotation returns besides the new state.
struct SymmetricRotationStep {
  Vec3 l_old;        ///< L(t - dt/2) [kg m^2/s]
  Vec3 l_new;        ///< L(t + dt/2) [kg m^2/s]
  double two_e_rot;  ///< L_mid . I_world(q(t))^-1 L_mid, L_mid = (l_old + l_new)/2 [J]
};

/// Per-body constants of advance_symmetric_rotation (the integrator keeps
/// them per particle, so the step itself needs no division).
struct SymmetricStepConstants {
  double decay = 0;      ///< (1 - a dt/2)/(1 + a dt/2), eq. 2
  double kick = 0;       ///< dt/(1 + a dt/2) [s], eq. 2 applied to L
  double inv_i1 = 0;     ///< 1/I1 [1/(kg m^2)] (symmetry axis)
  double inv_i2 = 0;     ///< 1/I2 = 1/I3 [1/(kg m^2)]
  double dt_inv_i2 = 0;  ///< dt/I2 [s/(kg m^2)]
  double dt = 0;         ///< [s]
  static SymmetricStepConstants of(const Vec3& inertia_body, double alpha, double dt) {
    const double half = 0.5 * alpha * dt;
    return {(1.0 - half) / (1.0 + half), dt / (1.0 + half), 1.0 / inertia_body.x, 1.0 / inertia_body.y,
            dt / inertia_body.y, dt};
  }
};

/// The parts of advance_symmetric_rotation (below), also run 8 bodies at a
/// time by the integrator's spheroid lanes (leapfrog_integrator.cpp), which
/// take the step angles' cos and sin by the polynomials alone.
/// The kick: L(t-dt/2) = I2 w + (I1 - I2)(e.w) e with e = q (1,0,0), then
/// L(t+dt/2) = decay L(t-dt/2) + kick M(t) (eq. 2 on L, damping eq. 29),
/// and the drift's half angles: precession |L| dt/(2 I2), spin about the
/// body axis (e.L)(1/I1 - 1/I2) dt/2.
struct SymmetricKick {
  Vec3 e_old;             ///< symmetry axis at t
  Vec3 l_old, l_new;      ///< L(t - dt/2), L(t + dt/2) [kg m^2/s]
  double inv_diff;        ///< 1/I1 - 1/I2 [1/(kg m^2)]
  double l2;              ///< |L(t + dt/2)|^2
  double half_dt_inv_i2;  ///< dt/(2 I2) [s/(kg m^2)]
  double precession2;     ///< (precession / 2)^2 [rad^2]
  double spin;            ///< spin / 2 [rad]
};
inline SymmetricKick symmetric_kick(const Quaternion& q, const Vec3& w, const Vec3& torque, double i1, double i2,
                                    const SymmetricStepConstants& k) {
  SymmetricKick out;
  out.inv_diff = k.inv_i1 - k.inv_i2;
  out.e_old = body_x_axis(q);
  out.l_old = i2 * w + ((i1 - i2) * dot(out.e_old, w)) * out.e_old;
  out.l_new = k.decay * out.l_old + k.kick * torque;
  out.l2 = norm2(out.l_new);
  out.half_dt_inv_i2 = 0.5 * k.dt_inv_i2;
  out.precession2 = out.l2 * (out.half_dt_inv_i2 * out.half_dt_inv_i2);
  out.spin = 0.5 * dot(out.l_new, out.e_old) * k.dt * out.inv_diff;
  return out;
}
/// The exact torque-free drift (as free_symmetric, with e known): Q(L^,
/// precession) q Q(x, spin) from the precession's cos cp and sin(x)/x sinc
/// (its vector part (sin x / |L|) L = sinc dt/(2 I2) L needs no |L|) and the
/// spin's cos cs and sin ss, renormalised by one Newton step for 1/|q|
/// (exact to O((|r|^2 - 1)^2)) instead of a square root and a division.
inline Quaternion symmetric_drift(const Quaternion& q, const SymmetricKick& kk, double cp, double sinc, double cs,
                                  double ss) {
  // the spin factor (cs, ss, 0, 0) written out
  const Quaternion qs{q.w * cs - q.x * ss, q.w * ss + q.x * cs, q.y * cs + q.z * ss, q.z * cs - q.y * ss};
  const Vec3 u = (sinc * kk.half_dt_inv_i2) * kk.l_new;
  const Quaternion r = Quaternion{cp, u.x, u.y, u.z} * qs;
  const double f = 1.5 - 0.5 * (r.w * r.w + r.x * r.x + r.y * r.y + r.z * r.z);
  return {f * r.w, f * r.x, f * r.y, f * r.z};
}
/// After the drift to q_new: w(t+dt/2) = L / I2 + (1/I1 - 1/I2)(e.L) e and
/// 2 E_rot = L_mid . I_world(q(t))^-1 L_mid, L_mid = (L_old + L_new)/2.
inline void symmetric_finish(const Quaternion& q_new, const SymmetricKick& kk, const SymmetricStepConstants& k,
                             Vec3& w, double& two_e_rot) {
  const Vec3 e_new = body_x_axis(q_new);
  w = k.inv_i2 * kk.l_new + (kk.inv_diff * dot(e_new, kk.l_new)) * e_new;
  const Vec3 l_mid = 0.5 * (kk.l_old + kk.l_new);
  const double el = dot(kk.e_old, l_mid);
  two_e_rot = k.inv_i2 * norm2(l_mid) + kk.inv_diff * el * el;
}

/// advance_rotation_omega for a symmetric body (inertia_body.y == .z, the
/// symmetry axis body x: spheroids), written with the world symmetry axis
/// e = q (1,0,0) instead of frame rotations (the same scheme; results differ
/// only by rounding):
///   L = I2 w + (I1 - I2)(e.w) e,   w = L / I2 + (1/I1 - 1/I2)(e.L) e,
///   L(t+dt/2) = decay L(t-dt/2) + kick M(t)   (eq. 2 on L, damping eq. 29),
///   q(t+dt)   = Q(L^, |L| dt/I2) q(t) Q(x, (e.L)(1/I1 - 1/I2) dt),
/// renormalised by one Newton step for 1/|q|. Cost ~170 flops, no square
/// root, division or library call for step angles <= 1/8 rad. Inline: the
/// integrator calls it for every spheroid and step.
inline SymmetricRotationStep advance_symmetric_rotation(Quaternion& q, Vec3& w, const Vec3& torque,
                                                        const Vec3& inertia, const SymmetricStepConstants& k) {
  const SymmetricKick kk = symmetric_kick(q, w, torque, inertia.x, inertia.y, k);
  if (kk.l2 > 0.0) {
    double cp, sinc, cs, ss;
    cos_sinc_of_square(kk.precession2, cp, sinc);
    cos_sin(kk.spin, cs, ss);
    q = symmetric_drift(q, kk, cp, sinc, cs, ss);
  }
  SymmetricRotationStep out;
  out.l_old = kk.l_old;
  out.l_new = kk.l_new;
  symmetric_finish(q, kk, k, w, out.two_e_rot);
  return out;
}

}  // namespace vt::dem
