// The damping models beside OD and ND (dem/viscous_contact_damping.h,
// dem/local_damping.h), against closed forms:
//   - viscous contact damping: head-on two-sphere impacts over two decades
//     of impact speed (0.01 to 1 m/s) return the set coefficient of
//     restitution within 2 % (e = 0.3, 0.6, 0.9), because the Tsuji form
//     makes e independent of the speed; without the dashpots e = 1; the
//     coefficient a follows from e by the dimensionless collision (round
//     trip, e(0) = 1, e falls with a; the dashpot is the stated a sqrt(m* K));
//   - Cundall's local damping: a particle on a linear spring (the integrator
//     with a force -k x) loses amplitude by (1 - a)/(1 + a) per cycle within
//     0.5 %; a particle moving without force keeps its velocity bit for bit
//     (where OD mass damping slows it);
//   - the energy budget closes with both models in a sheared packing
//     (relative balance error < 1e-3);
//   - scene keys: each model takes its own parameter, named errors otherwise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "support/scenes.h"
#include "virtual_triaxial/dem/leapfrog_integrator.h"
#include "virtual_triaxial/dem/local_damping.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/dem/viscous_contact_damping.h"
#include "virtual_triaxial/io/sample_file.h"
#include "virtual_triaxial/io/scene_error.h"
#include "virtual_triaxial/io/scene_parser.h"

using namespace vt::dem;

namespace {

constexpr double kR = 1e-3;  // [m]

/// Two equal spheres approaching head-on with relative speed v, gap g; damping
/// d. aspect > 1: prolate spheroids (semi-axes aspect kR, kR, kR) tip to tip
/// along their symmetry axes (x).
Simulation head_on(double v, double gap, double ct, const MassDamping& d, double aspect = 1.0) {
  const double l = 20 * kR, a = aspect * kR;
  PeriodicCell cell(Vec3{l, l, l});
  Particles p;
  const double x0 = 0.5 * l - a - 0.5 * gap, x1 = 0.5 * l + a + 0.5 * gap;
  const Vec3 s0 = cell.to_fractional({x0, 0.5 * l, 0.5 * l}), s1 = cell.to_fractional({x1, 0.5 * l, 0.5 * l});
  if (aspect > 1.0) {
    p.add_spheroid(0, a, kR, 2650, s0, Quaternion{}, {0.5 * v, 0, 0});
    p.add_spheroid(1, a, kR, 2650, s1, Quaternion{}, {-0.5 * v, 0, 0});
  } else {
    p.add_sphere(0, kR, 2650, s0, {0.5 * v, 0, 0});
    p.add_sphere(1, kR, 2650, s1, {-0.5 * v, 0, 0});
  }
  SimulationSettings s = vt::test::undamped(ct);
  s.damping = d;
  s.check_interval = 1000000;
  return Simulation(std::move(p), cell, s);
}

/// Restitution of one head-on impact at approach speed v: separation speed / v.
double restitution(double v, double e_set, double aspect = 1.0) {
  const Material m = vt::test::test_material();
  const double m_eff = 0.5 * m.density * sphere_volume(kR);
  const double k = 2.0 * m.young / (3.0 * (1 - m.poisson * m.poisson)) * std::sqrt(0.5 * kR);
  const double delta_max = std::pow(1.25 * m_eff * v * v / k, 0.4);  // undamped; the gap scales with it
  Simulation sim = head_on(v, 0.1 * delta_max, 0.05, MassDamping(DampingModel::Viscous, e_set), aspect);
  bool touched = false;
  for (int i = 0; i < 2000000; ++i) {
    sim.step();
    const Vec3 d = sim.cell().branch(sim.particles().frac[0], sim.particles().frac[1]);
    const bool overlap = norm(d) < 2 * aspect * kR;
    if (overlap) touched = true;
    if (touched && !overlap) break;
  }
  EXPECT_TRUE(touched);
  return (sim.particles().velocity[1].x - sim.particles().velocity[0].x) / v;
}

vt::io::SceneError scene_error(const std::string& damping) {
  const std::string yaml = "particles:\n  distribution: {count: 10, radius_min: 1.0e-3, radius_max: 1.0e-3}\n"
                           "stages:\n  - {type: relax, stop: {steps: 10}}\n" + damping;
  try {
    (void)vt::io::parse_scene(yaml);
  } catch (const vt::io::SceneError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted:\n" << yaml;
  return vt::io::SceneError("<none>", "<none>");
}

}  // namespace

TEST(ViscousContactDamping, TheCoefficientFollowsFromTheRestitution) {
  EXPECT_NEAR(ViscousContactDamping::restitution_of(0.0), 1.0, 1e-9);  // undamped Hertz impact is elastic
  double last = 1.0;
  for (double beta : {0.05, 0.2, 0.5, 1.0, 1.5}) {
    const double e = ViscousContactDamping::restitution_of(beta);
    EXPECT_LT(e, last) << beta;  // more damping, less rebound
    last = e;
    EXPECT_NEAR(ViscousContactDamping::coefficient_for(e) * std::sqrt(1.5), beta, 1e-6 * beta) << beta;
  }
  const ViscousContactDamping d(0.5);
  EXPECT_EQ(d.restitution(), 0.5);
  EXPECT_NEAR(d.eta(2.0, 8.0), d.coefficient() * 4.0, 1e-15);  // a sqrt(m* K)
  EXPECT_EQ(ViscousContactDamping(1.0).coefficient(), 0.0);
  EXPECT_THROW(ViscousContactDamping(0.0), std::invalid_argument);
  EXPECT_THROW(ViscousContactDamping(1.2), std::invalid_argument);
}

TEST(ViscousContactDamping, HeadOnImpactsReturnTheSetRestitutionAtEverySpeed) {
  for (double e_set : {0.3, 0.6, 0.9})
    for (double v : {0.01, 0.1, 1.0}) {
      const double e = restitution(v, e_set);
      EXPECT_NEAR(e / e_set, 1.0, 0.02) << "e = " << e_set << ", impact speed " << v << " m/s: got " << e;
    }
  EXPECT_NEAR(restitution(0.1, 1.0), 1.0, 1e-3);  // e = 1: no dashpots
}

TEST(ViscousContactDamping, HeadOnSpheroidImpactsReturnTheSetRestitution) {
  // Spheroids of aspect 1.5 tip to tip (the spheroid pair loop and its
  // contact lanes with dashpots): the restitution of a Hertz contact with
  // these dashpots depends on the set coefficient only (not on R* or m*),
  // so it must be the set one, as for spheres.
  for (double e_set : {0.3, 0.6, 0.9}) {
    const double e = restitution(0.1, e_set, 1.5);
    EXPECT_NEAR(e / e_set, 1.0, 0.02) << "e = " << e_set << ": got " << e;
  }
}

TEST(LocalDamping, ALinearOscillatorLosesAmplitudeByItsClosedFormPerCycle) {
  // One sphere on a spring F = -k (x - x_c) along x, integrated by the
  // Simulation's integrator (LeapfrogIntegrator) with local damping a.
  const double l = 0.1, k = 50.0;
  PeriodicCell cell(Vec3{l, l, l});
  for (double a : {0.05, 0.2, 0.5}) {
    Particles p;
    const double x_c = 0.5 * l, amp = 1e-3;
    p.add_sphere(0, kR, 2650, cell.to_fractional({x_c + amp, 0.5 * l, 0.5 * l}), {0, 0, 0});
    const double m = p.mass[0];
    const double period = 2 * M_PI * std::sqrt(m / k), dt = period / 2000;
    LeapfrogIntegrator integ;
    integ.set_coefficients(p, {0.0}, dt);
    integ.set_local_damping(LocalDamping(a));
    std::vector<Vec3> force(1), torque(1), build{p.frac[0]};
    std::vector<double> maxima;
    double x_prev = cell.to_cartesian(p.frac[0]).x - x_c;  // the start, at rest: not a maximum found
    for (int step = 0; step < 8000 && maxima.size() < 3; ++step) {
      const double x = cell.to_cartesian(p.frac[0]).x - x_c;
      force[0] = {-k * x, 0, 0};
      integ.advance(p, cell, force, torque, build, false);
      const double x_new = cell.to_cartesian(p.frac[0]).x - x_c;
      if (step > 0 && x > x_prev && x >= x_new && x > 0) {  // a maximum of x (the parabola through three points)
        const double c = 0.5 * (x_prev + x_new) - x, b = 0.5 * (x_new - x_prev);
        maxima.push_back(x - b * b / (4 * c));
      }
      x_prev = x;
    }
    ASSERT_EQ(maxima.size(), 3u) << a;
    const double want = (1 - a) / (1 + a);
    EXPECT_NEAR(maxima[0] / amp / want, 1.0, 0.005) << "a = " << a;
    EXPECT_NEAR(maxima[1] / maxima[0] / want, 1.0, 0.005) << "a = " << a;
    EXPECT_NEAR(maxima[2] / maxima[1] / want, 1.0, 0.005) << "a = " << a;
  }
}

TEST(LocalDamping, AParticleMovingWithoutForceKeepsItsVelocity) {
  const double l = 0.1;
  PeriodicCell cell(Vec3{l, l, l});
  auto fly = [&](const MassDamping& d) {
    Particles p;  // two spheres far apart (a Simulation needs two), moving in parallel
    p.add_sphere(0, kR, 2650, cell.to_fractional({0.25 * l, 0.5 * l, 0.5 * l}), {0.3, -0.2, 0.1}, {5.0, 0.0, -3.0});
    p.add_sphere(1, kR, 2650, cell.to_fractional({0.75 * l, 0.5 * l, 0.5 * l}), {0.3, -0.2, 0.1}, {5.0, 0.0, -3.0});
    SimulationSettings s = vt::test::undamped(0.3);
    s.damping = d;
    Simulation sim(std::move(p), cell, s);
    for (int i = 0; i < 1000; ++i) sim.step();
    return std::make_pair(sim.particles().velocity[0], sim.particles().omega[0]);
  };
  const auto local = fly(MassDamping(DampingModel::Local, 0.8));
  EXPECT_EQ(local.first.x, 0.3);
  EXPECT_EQ(local.first.y, -0.2);
  EXPECT_EQ(local.first.z, 0.1);
  EXPECT_EQ(local.second.x, 5.0);
  EXPECT_EQ(local.second.z, -3.0);
  const auto od = fly(MassDamping(DampingModel::OD, 0.01));  // mass damping slows a free particle
  EXPECT_LT(od.first.x, 0.3 * 0.999);
}

TEST(DampingModels, TheEnergyBudgetClosesWithEachModel) {
  // The same sheared packing with OD mass damping as the reference: the
  // new models' dissipation is counted, so their balance error is of the
  // same size as OD's (the step's own error), far below what they dissipate.
  const vt::dem::SimulationState start = vt::io::read_sample(VT_SOURCE_DIR "/tests/data/sample_200_100kPa.h5");
  auto run = [&](const MassDamping& d) {
    Simulation sim(start);
    sim.set_damping(d);
    const double r = 2e-5 / sim.time_scale().t0;
    sim.set_strain_rates({r, r, -2 * r});
    for (int i = 0; i < 3000; ++i) EXPECT_TRUE(sim.step(i % 100 == 0)) << to_string(d.model()) << ": " << sim.failure();
    EXPECT_TRUE(sim.step(true));
    return sim.energy();
  };
  const EnergyBudget od = run(MassDamping(DampingModel::OD, 0.05));
  for (const MassDamping& d : {MassDamping(DampingModel::Viscous, 0.5), MassDamping(DampingModel::Local, 0.7)}) {
    const EnergyBudget e = run(d);
    const double err = std::fabs(e.relative_balance_error());
    std::printf("%s: damping %.3e J, balance error %.2e (OD xi 0.05: %.2e)\n", to_string(d.model()), e.damping, err,
                std::fabs(od.relative_balance_error()));
    EXPECT_GT(e.damping, 0.0) << to_string(d.model());
    EXPECT_LT(err, 2.0 * std::fabs(od.relative_balance_error()) + 1e-4) << to_string(d.model());
    EXPECT_LT(err * e.scale(), 0.05 * e.damping) << to_string(d.model()) << ": the dissipation is not all counted";
  }
}

TEST(DampingModels, SceneKeysNameTheField) {
  const vt::io::SceneConfig v = vt::io::parse_scene(
      "particles:\n  distribution: {count: 10, radius_min: 1.0e-3, radius_max: 1.0e-3}\n"
      "stages:\n  - {type: relax, stop: {steps: 10}}\ndamping: {model: viscous, restitution: 0.7}\n");
  EXPECT_EQ(v.damping.model(), DampingModel::Viscous);
  EXPECT_EQ(v.damping.ratio(), 0.7);
  struct Case {
    const char* damping;
    const char* field;
    const char* says;
  };
  for (const Case& c : {Case{"damping: {model: viscous}\n", "damping.restitution", "required"},
                        Case{"damping: {model: viscous, restitution: 1.5}\n", "damping.restitution", "(0, 1]"},
                        Case{"damping: {model: viscous, restitution: 0}\n", "damping.restitution", "(0, 1]"},
                        Case{"damping: {model: local, coefficient: 1.0}\n", "damping.coefficient", "[0, 1)"},
                        Case{"damping: {model: local}\n", "damping.coefficient", "required"},
                        Case{"damping: {model: OD, restitution: 0.5}\n", "damping.restitution", "not a parameter"},
                        Case{"damping: {model: local, ratio: 0.1}\n", "damping.ratio", "not a parameter"},
                        Case{"damping: {model: wet}\n", "damping.model", "viscous"}}) {
    const vt::io::SceneError e = scene_error(c.damping);
    EXPECT_EQ(e.field(), c.field) << c.damping;
    EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << c.damping << " -> " << e.what();
  }
  Simulation sim(vt::io::read_sample(VT_SOURCE_DIR "/tests/data/sample_200_100kPa.h5"));
  try {
    sim.set_damping(MassDamping(DampingModel::Local, 1.5));
    ADD_FAILURE() << "set_damping accepted a = 1.5";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("damping.coefficient"), std::string::npos) << e.what();
  }
  EXPECT_EQ(sim.settings().damping.model(), DampingModel::OD);  // unchanged
}
