// LeapfrogIntegrator's spheroid lanes (leapfrog_integrator.h,
// advance_spheroid_lanes): one step of a mixed sample (spheroids of several
// shapes and spins, spheres, a spheroid at rest, one spinning beyond the
// small-angle polynomials) against the rigid-body step of rigid_rotation.h
// particle by particle (eq. 2 kick, exact torque-free drift), and the
// step's sums against their definitions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "virtual_triaxial/dem/leapfrog_integrator.h"
#include "virtual_triaxial/dem/particles.h"
#include "virtual_triaxial/dem/periodic_cell.h"
#include "virtual_triaxial/dem/rigid_rotation.h"

using namespace vt::dem;

namespace {

double max_abs(const Vec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }
double max_abs(const Quaternion& q) {
  return std::max({std::fabs(q.w), std::fabs(q.x), std::fabs(q.y), std::fabs(q.z)});
}
Quaternion minus(const Quaternion& a, const Quaternion& b) { return {a.w - b.w, a.x - b.x, a.y - b.y, a.z - b.z}; }

}  // namespace

TEST(IntegratorLanes, SpheroidLanesTakeTheRigidBodyStepOfEveryParticle) {
  // 45 particles (five full groups of 8 and a tail of 5): spheroids of aspect
  // 1 to 2 with random orientations, spins and torques (the group 32-39 holds
  // only those, so it is stored by shuffles, the others lane by lane); spheres at 3, 12 and
  // 30 (their lanes take the scalar step; a sphere's orientation is not
  // integrated); a spheroid at rest without torque at 17 (L = 0: the
  // orientation must stay exactly as it is); one at 21 spinning so fast that
  // the half step angle exceeds 1/16 rad (std::cos and std::sin in the
  // scalar step); one at 9 with I2 != I3 (as a file may hold: the general
  // step). Every particle must match the reference step of rigid_rotation.h
  // (advance_rotation_omega for spheroids, eq. 2 for spheres) to rounding,
  // with damping alpha > 0, and every sum of the step its definition.
  const double l = 0.05, dt = 2e-6, rho = 2650, b = 4e-4;
  const PeriodicCell cell(Vec3{l, l, l});
  std::mt19937_64 g(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto vec = [&](double s) { return Vec3{s * u(g), s * u(g), s * u(g)}; };
  Particles p;
  const int n = 45;
  for (int i = 0; i < n; ++i) {
    const Vec3 s{0.5 + 0.4 * u(g), 0.5 + 0.4 * u(g), 0.5 + 0.4 * u(g)};
    if (i == 3 || i == 12 || i == 30) {
      p.add_sphere(i, b, rho, s, vec(0.1), vec(200.0));
      continue;
    }
    Quaternion q{u(g), u(g), u(g), u(g)};
    q = normalized(q);
    const double a = b * (1.0 + 0.5 * (1.0 + u(g)));
    Vec3 w = vec(300.0);
    if (i == 17) w = {};
    if (i == 21) w = {4e5, -3e5, 5e5};  // |w| dt / 2 ~ 0.7 rad > 1/16
    p.add_spheroid(i, a, b, rho, s, q, vec(0.1), w);
  }
  p.inertia[9].z *= 1.1;
  std::vector<double> alpha(n);
  for (int i = 0; i < n; ++i) alpha[i] = 50.0 + i;
  std::vector<Vec3> force(n), torque(n);
  for (int i = 0; i < n; ++i) {
    force[i] = vec(1e-3);
    torque[i] = i == 17 ? Vec3{} : vec(1e-7);
  }
  // the group 32-39 takes the shuffled stores only while every lane holds:
  // symmetric spheroids, L != 0, half step angles below 1/16 rad
  for (int i = 32; i < 40; ++i) {
    ASSERT_EQ(p.shape[i], Shape::Spheroid) << i;
    ASSERT_EQ(p.inertia[i].y, p.inertia[i].z) << i;
    ASSERT_GT(norm(p.omega[i]), 0.0) << i;
    ASSERT_LT(norm(p.omega[i]) * dt / 2, 1.0 / 16) << i;
  }
  const Particles before = p;
  LeapfrogIntegrator integ;
  integ.set_coefficients(p, alpha, dt);
  const std::vector<Vec3> build = p.frac;
  Particles unmeasured = p;
  const IntegrationSums sums = integ.advance(p, cell, force, torque, build, true);
  integ.advance(unmeasured, cell, force, torque, build, false);

  double kinetic_t = 0, kinetic_r = 0, damping = 0, moment = 0, max_w2 = 0, max_d2 = 0;
  for (int i = 0; i < n; ++i) {
    SCOPED_TRACE(i);
    const double half = 0.5 * alpha[i] * dt;
    const double decay = (1.0 - half) / (1.0 + half);
    const Vec3 v_new = decay * before.velocity[i] + (dt / ((1.0 + half) * before.mass[i])) * force[i];
    EXPECT_LT(max_abs(p.velocity[i] - v_new), 1e-15 * (1.0 + max_abs(v_new)));
    const Vec3 x_new = cell.to_cartesian(before.frac[i]) + dt * v_new;
    EXPECT_LT(max_abs(cell.to_cartesian(p.frac[i]) - x_new), 1e-15);
    const Vec3 v_mid = 0.5 * (before.velocity[i] + v_new);
    kinetic_t += 0.5 * before.mass[i] * norm2(v_mid);
    damping += alpha[i] * dt * before.mass[i] * norm2(v_mid);
    max_w2 = std::max(max_w2, norm2(p.omega[i]));
    max_d2 = std::max(max_d2, norm2(cell.to_cartesian(p.frac[i]) - cell.to_cartesian(before.frac[i])));
    // the same state without measuring
    EXPECT_EQ(unmeasured.velocity[i].x, p.velocity[i].x);
    EXPECT_EQ(unmeasured.omega[i].y, p.omega[i].y);
    EXPECT_EQ(unmeasured.orientation[i].z, p.orientation[i].z);
    EXPECT_EQ(unmeasured.frac[i].x, p.frac[i].x);
    if (p.shape[i] == Shape::Sphere) {
      const Vec3 w_new = decay * before.omega[i] + (dt / ((1.0 + half) * before.inertia[i].x)) * torque[i];
      EXPECT_LT(max_abs(p.omega[i] - w_new), 1e-13 * (1.0 + max_abs(w_new)));
      EXPECT_EQ(max_abs(minus(p.orientation[i], before.orientation[i])), 0.0);  // not integrated
      const Vec3 w_mid = 0.5 * (before.omega[i] + p.omega[i]);
      kinetic_r += 0.5 * before.inertia[i].x * norm2(w_mid);
      damping += alpha[i] * dt * before.inertia[i].x * norm2(w_mid);
      moment += before.inertia[i].x / dt * norm(p.omega[i] - before.omega[i]);
      continue;
    }
    {  // E_rot = L_mid . I_world(q(t))^-1 L_mid / 2, |dL|/dt (leapfrog_integrator.h)
      const Vec3 l_old = angular_momentum_world(before.orientation[i], before.omega[i], before.inertia[i]);
      const Vec3 l_new = angular_momentum_world(p.orientation[i], p.omega[i], before.inertia[i]);
      const Vec3 l_mid = 0.5 * (l_old + l_new);
      const double two_e = dot(l_mid, angular_velocity_world(before.orientation[i], l_mid, before.inertia[i]));
      kinetic_r += 0.5 * two_e;
      damping += alpha[i] * dt * two_e;
      moment += norm(l_new - l_old) / dt;
    }
    Quaternion q = before.orientation[i];
    Vec3 w = before.omega[i];
    advance_rotation_omega(q, w, torque[i], before.inertia[i], alpha[i], dt);
    if (i == 17) {  // at rest: the orientation is kept bit for bit
      EXPECT_EQ(p.orientation[i].w, before.orientation[i].w);
      EXPECT_EQ(p.orientation[i].x, before.orientation[i].x);
      EXPECT_EQ(max_abs(p.omega[i]), 0.0);
    }
    EXPECT_LT(max_abs(minus(p.orientation[i], q)), 1e-15);
    EXPECT_LT(max_abs(p.omega[i] - w), 1e-13 * max_abs(w) + 1e-300);
  }
  // the sums by their definitions
  EXPECT_NEAR(sums.kinetic_translational, kinetic_t, 1e-13 * kinetic_t);
  EXPECT_NEAR(sums.kinetic_rotational, kinetic_r, 1e-12 * kinetic_r);
  EXPECT_NEAR(sums.damping_dissipation, damping, 1e-12 * damping);
  EXPECT_NEAR(sums.sum_inertia_moment, moment, 1e-9 * moment);
  EXPECT_NEAR(sums.max_spin2, max_w2, 1e-13 * max_w2);
  EXPECT_NEAR(sums.max_displacement2, max_d2, 1e-9 * max_d2);
  EXPECT_TRUE(sums.finite);
  double max_v2 = 0;
  for (int i = 0; i < n; ++i) max_v2 = std::max(max_v2, norm2(p.velocity[i]));
  EXPECT_EQ(sums.max_speed2, max_v2);
}
