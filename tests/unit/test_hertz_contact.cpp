// Two-sphere contact tests against Hertz and Mindlin closed forms.
#include <gtest/gtest.h>

#include <cmath>

#include "support/scenes.h"
#include "virtual_triaxial/dem/contact_forces.h"
#include "virtual_triaxial/dem/simulation.h"

using namespace vt::dem;

namespace {

constexpr double kR = 1e-3;

/// Two equal spheres on the x axis in a big periodic cell, approaching with
/// relative speed v (each +-v/2), gap g between surfaces.
Simulation head_on(double v, double gap, double ct) {
  const double l = 20 * kR;
  PeriodicCell cell(Vec3{l, l, l});
  Particles p;
  const double x0 = 0.5 * l - kR - 0.5 * gap, x1 = 0.5 * l + kR + 0.5 * gap;
  p.add_sphere(0, kR, 2650, cell.to_fractional({x0, 0.5 * l, 0.5 * l}), {0.5 * v, 0, 0});
  p.add_sphere(1, kR, 2650, cell.to_fractional({x1, 0.5 * l, 0.5 * l}), {-0.5 * v, 0, 0});
  SimulationSettings s = vt::test::undamped(ct);
  s.check_interval = 1000000;
  return Simulation(std::move(p), cell, s);
}

double overlap_of(const Simulation& sim) {
  const Vec3 d = sim.cell().branch(sim.particles().frac[0], sim.particles().frac[1]);
  return 2 * kR - norm(d);
}

}  // namespace

TEST(HertzImpact, DurationOverlapAndRestitutionMatchTheory) {
  const Material m = vt::test::test_material();
  const double v = 1.0;                         // approach speed [m/s]
  const double mass = m.density * sphere_volume(kR);
  const double m_eff = 0.5 * mass;
  const double r_eff = 0.5 * kR;
  const double k = 2.0 * m.young / (3.0 * (1 - m.poisson * m.poisson)) * std::sqrt(r_eff);  // F = k delta^1.5
  const double delta_max = std::pow(1.25 * m_eff * v * v / k, 0.4);
  // t_c = 2 (delta_max / v) * int_0^1 (1 - x^2.5)^-1/2 dx = 2 sqrt(pi) G(7/5)/G(9/10) delta_max/v
  const double t_c = 2.0 * std::sqrt(M_PI) * std::tgamma(1.4) / std::tgamma(0.9) * delta_max / v;

  Simulation sim = head_on(v, 0.1 * delta_max, 0.005);
  const double dt = sim.dt();
  ASSERT_GT(t_c / dt, 200.0) << "time step too coarse for the test";
  double prev = overlap_of(sim), t_in = -1, t_out = -1, max_ov = 0;
  for (int i = 0; i < 100000 && t_out < 0; ++i) {
    const double t0 = sim.time();
    sim.step();
    const double ov = overlap_of(sim);
    max_ov = std::max(max_ov, ov);
    // positions at t0+dt; linear interpolation of the zero crossing
    if (prev <= 0 && ov > 0) t_in = t0 + dt * (-prev) / (ov - prev);
    if (prev > 0 && ov <= 0 && t_in >= 0) t_out = t0 + dt * prev / (prev - ov);
    prev = ov;
  }
  ASSERT_GT(t_out, 0) << "the spheres never separated";
  EXPECT_NEAR((t_out - t_in) / t_c, 1.0, 0.005);
  EXPECT_NEAR(max_ov / delta_max, 1.0, 0.005);
  const double v_after = sim.particles().velocity[1].x - sim.particles().velocity[0].x;
  EXPECT_NEAR(v_after / v, 1.0, 1e-3) << "restitution of an undamped elastic impact";
  EXPECT_NEAR(norm(sim.particles().omega[0]), 0.0, 1e-12);
}

TEST(HertzImpact, NormalForceAndStiffnessFollowEquations107And116) {
  const Material m = vt::test::test_material();
  HertzMindlin law(m);
  const double delta = 3e-6, r_eff = 0.4e-3;
  const double fn = 2 * m.young / (3 * (1 - m.poisson * m.poisson)) * std::sqrt(r_eff * delta * delta * delta);
  EXPECT_NEAR(law.normal_force(delta, r_eff) / fn, 1.0, 1e-14);
  // K_n = dF/ddelta, checked by a central difference
  const double h = 1e-12;
  const double kn_fd = (law.normal_force(delta + h, r_eff) - law.normal_force(delta - h, r_eff)) / (2 * h);
  EXPECT_NEAR(law.normal_stiffness(delta, r_eff) / kn_fd, 1.0, 1e-6);
  EXPECT_NEAR(law.normal_stiffness(delta, r_eff), m.young / (1 - m.poisson * m.poisson) * std::sqrt(r_eff * delta),
              1e-9 * law.normal_stiffness(delta, r_eff));
}

// Zero overlap (a pair at exactly R_i + R_j by rounding) with a stored
// spring: K_t = 0 and mu F_n = 0, so the spring is dropped; the dissipation
// is the limit of mu F_n (|F_t| - mu F_n) / K_t as delta -> 0 (it scales as
// delta), i.e. 0 -- not 0/0.
TEST(MindlinTangential, ZeroOverlapDropsTheSpringWithoutNaN) {
  const HertzMindlin law(vt::test::test_material());
  Vec3 spring{0.0, 2e-3, -1e-3};
  const ContactResult r = law.evaluate({1.0, 0.0, 0.0}, 0.0, 0.4e-3, {0.0, 1e-9, 0.0}, spring);
  EXPECT_EQ(r.friction_dissipation, 0.0);
  EXPECT_EQ(r.elastic_energy, 0.0);
  EXPECT_EQ(norm(spring), 0.0);
  EXPECT_EQ(norm(r.force_on_j), 0.0);
  // and just above zero the dissipation is finite and small (continuity)
  Vec3 spring2{0.0, 2e-3, -1e-3};
  const ContactResult r2 = law.evaluate({1.0, 0.0, 0.0}, 1e-18, 0.4e-3, {0.0, 1e-9, 0.0}, spring2);
  EXPECT_TRUE(std::isfinite(r2.friction_dissipation));
  EXPECT_LT(r2.friction_dissipation, 1e-12);
}

// Constant normal overlap, imposed tangential sliding velocity: the spring
// follows F_t = K_t u (incremental Mindlin, eq. 113-117) until it reaches
// mu F_n, then slides at mu F_n.
TEST(MindlinTangential, StiffnessThenCoulombSliding) {
  const Material mat = vt::test::test_material(0.5);
  const double l = 20 * kR, delta = 2e-6;
  PeriodicCell cell(Vec3{l, l, l});
  Particles p;
  const Vec3 c{0.5 * l, 0.5 * l, 0.5 * l};
  const double u_dot = 1e-3;  // relative tangential speed [m/s] along y
  p.add_sphere(0, kR, 2650, cell.to_fractional(c - Vec3{kR - 0.5 * delta, 0, 0}));
  p.add_sphere(1, kR, 2650, cell.to_fractional(c + Vec3{kR - 0.5 * delta, 0, 0}), {0, u_dot, 0});
  NeighborList list;
  list.set_skin(0.1 * kR);
  list.build(p, cell);
  HertzMindlin law(mat);
  ContactForces cf;
  std::vector<Vec3> f, t;
  const double dt = 1e-7;
  const double r_eff = 0.5 * kR;
  const double fn = law.normal_force(delta, r_eff);
  const double kt = law.tangential_ratio() * law.normal_stiffness(delta, r_eff);
  EXPECT_NEAR(law.tangential_ratio(), 2 * (1 - 0.3) / (2 - 0.3), 1e-15);
  const double u_slip = mat.friction * fn / kt;  // displacement at which sliding starts
  const int steps = static_cast<int>(2.0 * u_slip / (u_dot * dt));
  double dissipated = 0;
  for (int k = 1; k <= steps; ++k) {
    const ContactSums s = cf.compute(p, cell, list, law, dt, false, f, t);
    dissipated += s.friction_dissipation;
    const double u = k * u_dot * dt;
    const double expected = std::min(kt * u, mat.friction * fn);
    // force on particle 1 opposes its motion (+y)
    ASSERT_NEAR(-f[1].y, expected, 1e-9 * mat.friction * fn) << "step " << k;
    ASSERT_NEAR(f[1].x, fn, 1e-12 * fn);
    ASSERT_NEAR(f[0].y + f[1].y, 0.0, 1e-15 * fn) << "action = reaction";
  }
  // Energy dissipated by sliding = mu F_n x slip distance.
  const double slip = steps * u_dot * dt - u_slip;
  EXPECT_NEAR(dissipated / (mat.friction * fn * slip), 1.0, 1e-3);
  // Torques from the tangential force: |T| = l F_t, l = R - delta/2.
  EXPECT_NEAR(norm(t[0]) / ((kR - 0.5 * delta) * mat.friction * fn), 1.0, 1e-12);
}
