// Time step from the contacts (dem/contact_time_step.h): on two spheres
// pressed together the step equals the closed-form critical step of the
// Hertz pair, 2 / omega with omega^2 = 3.5 K_t (1/m_i + 1/m_j) (the rolling-
// sliding mode, stiffer than the normal one); the step follows the overlap;
// a run continues bit for bit through its state and a sample file; bad
// settings name the field.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "support/scenes.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/io/qs_advice.h"
#include "virtual_triaxial/io/sample_file.h"
#include "virtual_triaxial/io/scene_builder.h"
#include "virtual_triaxial/io/scene_parser.h"

namespace fs = std::filesystem;
using namespace vt::dem;

namespace {

constexpr double kPi = 3.14159265358979323846;

SimulationSettings contact_settings(double safety) {
  SimulationSettings s = vt::test::undamped(0.3);
  s.time_step_basis = TimeStepBasis::Contacts;
  s.time_step_safety = safety;
  s.time_step_max_ratio = 100.0;
  return s;
}

/// Two spheres of radii r1, r2 at rest in a large cell, overlapping by delta.
Simulation pair(double r1, double r2, double delta, double safety) {
  const PeriodicCell cell(Vec3{0.05, 0.05, 0.05});
  Particles p;
  const double rho = 2650.0;
  p.add_sphere(0, r1, rho, {0.5, 0.5, 0.5});
  p.add_sphere(1, r2, rho, {0.5 + (r1 + r2 - delta) / 0.05, 0.5, 0.5});
  return Simulation(std::move(p), cell, contact_settings(safety));
}

/// Closed form: K_n = E/(1-nu^2) sqrt(R* delta), K_t = 2(1-nu)/(2-nu) K_n,
/// spheres I = 2/5 m R^2 so R^2/I = 2.5/m: omega_t^2 = 3.5 K_t (1/m1 + 1/m2).
double closed_form(double r1, double r2, double delta) {
  const Material m = vt::test::test_material();
  const double r_star = r1 * r2 / (r1 + r2);
  const double kn = m.young / (1 - m.poisson * m.poisson) * std::sqrt(r_star * delta);
  const double kt = 2 * (1 - m.poisson) / (2 - m.poisson) * kn;
  const double m1 = m.density * 4.0 / 3.0 * kPi * r1 * r1 * r1, m2 = m.density * 4.0 / 3.0 * kPi * r2 * r2 * r2;
  const double inv_m = 1 / m1 + 1 / m2;
  EXPECT_GT(3.5 * kt * inv_m, kn * inv_m) << "the rolling-sliding mode is the stiffer one";
  return 2.0 / std::sqrt(3.5 * kt * inv_m);
}

}  // namespace

TEST(ContactTimeStep, TwoSpheresTakeTheClosedFormHertzCriticalStep) {
  for (const double r2 : {1e-3, 0.6e-3}) {
    const double r1 = 1e-3, delta = 1e-6, safety = 0.5;
    Simulation sim = pair(r1, r2, delta, safety);
    ASSERT_TRUE(sim.step(false)) << sim.failure();
    const double expected = closed_form(r1, r2, delta);
    // the overlap comes from positions rounded to ~1e-16 of the cell (5 cm)
    EXPECT_NEAR(sim.contact_critical_step().dt / expected, 1.0, 1e-8) << "r2 " << r2;
    EXPECT_EQ(sim.contact_critical_step().contacts, 1);
    EXPECT_EQ(sim.dt(), safety * sim.contact_critical_step().dt);
    EXPECT_GT(sim.dt(), sim.time_scale().t0) << "soft Hertz contact: far above T0";
  }
}

TEST(ContactTimeStep, StepFallsAsTheOverlapGrowsAndHasACeiling) {
  // dt ~ K^-1/2 ~ delta^-1/4: 16 x the overlap halves the step
  Simulation a = pair(1e-3, 1e-3, 1e-7, 0.5), b = pair(1e-3, 1e-3, 16e-7, 0.5);
  ASSERT_TRUE(a.step(false));
  ASSERT_TRUE(b.step(false));
  EXPECT_NEAR(a.dt() / b.dt(), 2.0, 1e-6);
  // apart: no contact, the ceiling r_max T0
  SimulationSettings s = contact_settings(0.5);
  s.time_step_max_ratio = 1.5;
  Particles p;
  p.add_sphere(0, 1e-3, 2650.0, {0.2, 0.5, 0.5});
  p.add_sphere(1, 1e-3, 2650.0, {0.7, 0.5, 0.5});
  Simulation apart(std::move(p), PeriodicCell(Vec3{0.05, 0.05, 0.05}), s);
  ASSERT_TRUE(apart.step(false));
  EXPECT_EQ(apart.contact_critical_step().contacts, 0);
  EXPECT_EQ(apart.dt(), 1.5 * apart.time_scale().t0);
}

TEST(ContactTimeStep, RunContinuesBitForBitThroughStateAndSampleFile) {
  vt::test::CloudScene sc = vt::test::polydisperse_cloud(300, 0.9, 5);
  SimulationSettings s = contact_settings(0.35);
  s.damping = MassDamping(DampingModel::OD, 0.05);
  s.time_step_max_ratio = 2.0;
  Simulation straight(std::move(sc.particles), sc.cell, s);
  const double rate = 1e-4 / straight.time_scale().t0;
  straight.set_strain_rates({-rate, -rate, -rate});
  ASSERT_EQ(straight.run(1050), 1050);  // refreshes at 0, 100, ..., 1000
  const SimulationState mid = straight.state();
  const std::string path = (fs::temp_directory_path() / ("vt_cts_" + std::to_string(::getpid()) + ".h5")).string();
  vt::io::write_sample(path, mid, {});
  Simulation from_state(mid), from_file(vt::io::read_sample(path));
  fs::remove(path);
  EXPECT_EQ(from_file.dt(), straight.dt());
  ASSERT_EQ(straight.run(300), 300);
  ASSERT_EQ(from_state.run(300), 300);
  ASSERT_EQ(from_file.run(300), 300);
  EXPECT_LT(straight.dt(), straight.time_scale().t0 * 2.0) << "contacts formed and set the step";
  const auto& a = straight.particles().frac;
  for (const Simulation* other : {&from_state, &from_file}) {
    EXPECT_EQ(other->dt(), straight.dt());
    EXPECT_EQ(std::memcmp(a.data(), other->particles().frac.data(), a.size() * sizeof(Vec3)), 0);
  }
}

TEST(ContactTimeStep, BadSettingsNameTheField) {
  vt::test::CloudScene sc = vt::test::polydisperse_cloud(50, 1.5, 3);
  SimulationSettings s = contact_settings(1.5);
  try {
    Simulation sim(std::move(sc.particles), sc.cell, s);
    FAIL() << "safety 1.5 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("time_step_safety"), std::string::npos) << e.what();
  }
}

// triax_qs / ~predict_quasi_static plan a scene's shear with the time step the
// run will use: with the contacts basis that is the step derived at the first
// force evaluation, not the c_t that a Simulation reports before it.
TEST(ContactTimeStep, QsAdvicePlansWithTheStepFromTheContacts) {
  const std::string yaml = std::string("particles: {sample_file: ") + VT_SOURCE_DIR +
                           "/tests/data/sample_200_100kPa.h5}\n"
                           "time_step_basis: contacts\n"
                           "stages:\n"
                           "  - {type: drained_shear, confining_pressure: 1.0e5, strain_rate_dimensionless: 1.0e-5,"
                           " stop: {axial_strain: 0.01}}\n";
  const vt::io::SceneConfig scene = vt::io::parse_scene(yaml);
  const Simulation sim = vt::io::build_simulation(scene);
  EXPECT_DOUBLE_EQ(sim.time_scale().ct, 0.3);  // the scene default c_t, unused by the contacts basis
  Simulation probe(sim.state());
  ASSERT_TRUE(probe.step(true));
  const double ct = probe.time_scale().ct;
  EXPECT_GT(ct, 0.5) << "a 100 kPa Hertz packing allows more than c_t 0.3";
  const vt::io::QsAdvice a = vt::io::build_qs_advice(scene, sim, 1e-7);
  EXPECT_EQ(a.time_step_ratio, ct);
  // steps = eps_final / (c_t eps') (qs::plan_run)
  EXPECT_NEAR(a.plan_requested.steps, 0.01 / (ct * 1e-5), 1.0);
}
