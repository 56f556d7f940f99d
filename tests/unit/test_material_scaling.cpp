// `material.*` beside a `particles.sample_file` (issue 15, item 5; chapter 3):
// density and Young's modulus are scaled into the loaded sample keeping every
// dimensionless quantity, so
//   * the same eps' gives the same dimensionless history, bit for bit with
//     power-of-two factors (section 3.3.2);
//   * density x 4 at a fixed strain rate [1/s] = the base sample at twice
//     the rate (mass scaling = a higher eps', table 7 D-1/D-1e), bit for bit;
//   * stiffness / 16 keeps sigma_bar, so the stress in Pa falls 16x: holding
//     the same confining pressure in Pa means a 16x higher sigma_bar, and a
//     fixed rate [1/s] is a 4x higher eps' (table 7 D-2/D-2e);
// a different Poisson ratio is refused naming the field. Chapter 5's "equal
// xi eps' behaves alike above the optimum" is checked on a short shear with
// a stated tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "virtual_triaxial/io/sample_file.h"
#include "virtual_triaxial/io/scene_builder.h"
#include "virtual_triaxial/io/scene_error.h"
#include "virtual_triaxial/io/scene_parser.h"

namespace {

const std::string kSample = std::string(VT_SOURCE_DIR) + "/tests/data/sample_200_100kPa.h5";

vt::dem::Simulation load(const std::string& material, const std::string& damping = "{model: OD, ratio: 0.003}") {
  const std::string yaml = "particles: {sample_file: " + kSample + "}\n" +
                           (material.empty() ? "" : "material: " + material + "\n") + "damping: " + damping +
                           "\ntime_step_ratio: 0.3\nstages:\n  - {type: relax, stop: {steps: 1}}\n";
  return vt::io::build_simulation(vt::io::parse_scene(yaml, ""));
}

struct History {
  std::vector<double> sigma_bar, frac, vel_bar;
  double mean_i_mom = 0.0, q_end = 0.0, p_end = 0.0;
};

// Axial compression of z at `rate` [1/s], lateral axes fixed, `steps` steps.
History shear(vt::dem::Simulation& sim, double rate, int steps) {
  sim.set_strain_rates(vt::dem::Vec3{0.0, 0.0, -rate});
  History h;
  const double e = sim.state().settings.material.young;
  for (int k = 0; k < steps; ++k) {
    if (!sim.step(true)) {
      ADD_FAILURE() << sim.failure();
      break;
    }
    const auto m = sim.measures();
    for (int a = 0; a < 3; ++a) h.sigma_bar.push_back(m.stress(a, a) / e);
    h.mean_i_mom += m.moment_index / steps;
    h.q_end = m.q;
    h.p_end = m.p;
  }
  const double v0 = sim.time_scale().l0 / sim.time_scale().t0;
  for (std::size_t i = 0; i < sim.particles().size(); ++i)
    for (int a = 0; a < 3; ++a) {
      h.frac.push_back(sim.particles().frac[i][a]);
      h.vel_bar.push_back(sim.particles().velocity[i][a] / v0);
    }
  return h;
}

void expect_bits(const std::vector<double>& a, const std::vector<double>& b, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a[i], &b[i], sizeof(double)) != 0) {
      ADD_FAILURE() << what << " differ first at " << i << ": " << a[i] << " vs " << b[i];
      return;
    }
}

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

}  // namespace

TEST(MaterialScaling, DensityAndModulusKeepTheDimensionlessHistoryBitForBit) {
  const auto m = vt::io::read_sample(kSample).settings.material;
  for (const char* damping : {"{model: OD, ratio: 0.003}", "{model: ND, ratio: 0.005}"}) {
    auto base = load("", damping);
    auto scaled = load("{density: " + num(4 * m.density) + ", young_modulus: " + num(16 * m.young) + "}", damping);
    EXPECT_EQ(scaled.time_scale().t0, base.time_scale().t0 / 2);   // sqrt(4/16)
    const double eps_prime = 1e-5;
    const History a = shear(base, eps_prime / base.time_scale().t0, 600);
    const History b = shear(scaled, eps_prime / scaled.time_scale().t0, 600);
    expect_bits(a.sigma_bar, b.sigma_bar, "sigma_bar history");
    expect_bits(a.frac, b.frac, "fractional positions");
    expect_bits(a.vel_bar, b.vel_bar, "dimensionless velocities");
  }
}

TEST(MaterialScaling, DensityTimesFourAtAFixedRateIsTheBaseAtTwiceTheRate) {
  const auto m = vt::io::read_sample(kSample).settings.material;
  auto base = load("");
  auto heavy = load("{density: " + num(4 * m.density) + "}");
  const double rate = 1e-5 / base.time_scale().t0;   // [1/s]
  const History a = shear(base, 2 * rate, 600);
  const History b = shear(heavy, rate, 600);
  expect_bits(a.sigma_bar, b.sigma_bar, "sigma_bar history");
  expect_bits(a.frac, b.frac, "fractional positions");
}

TEST(MaterialScaling, SofterByASixteenthKeepsSigmaBarSoTheStressFalls16x) {
  const auto m = vt::io::read_sample(kSample).settings.material;
  auto base = load("");
  auto soft = load("{young_modulus: " + num(m.young / 16) + "}");
  EXPECT_EQ(soft.time_scale().t0, 4 * base.time_scale().t0);   // a fixed rate [1/s] is 4x the eps'
  const double rate = 1e-5 / base.time_scale().t0;
  const History a = shear(base, 4 * rate, 300);
  const History b = shear(soft, rate, 300);
  expect_bits(a.sigma_bar, b.sigma_bar, "sigma_bar history");
  EXPECT_EQ(b.p_end * 16, a.p_end);   // same sigma_bar: 16x less in Pa, so 100 kPa would be 16x sigma_bar
}

TEST(MaterialScaling, ADifferentPoissonRatioIsRefusedNamingTheField) {
  const auto m = vt::io::read_sample(kSample).settings.material;
  try {
    load("{poisson_ratio: " + num(m.poisson == 0.25 ? 0.2 : 0.25) + "}");
    FAIL() << "accepted";
  } catch (const vt::io::SceneError& e) {
    EXPECT_EQ(e.field(), "material.poisson_ratio");
    EXPECT_NE(std::string(e.what()).find("prepare a new sample"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(load("{poisson_ratio: " + num(m.poisson) + "}"));   // the sample's own value
}

// Chapter 5.7 / eq. 86: above the optimum only xi eps' matters. On the
// 200-sphere sample, 1 % axial strain: (xi 2 %, eps' 1e-5) against (xi 4 %,
// eps' 5e-6) -- same product -- give mean I_mom and q within 10 % of each
// other, while (xi 2 %, eps' 5e-6), half the product, differs by more.
TEST(MaterialScaling, EqualXiEpsPrimeAboveTheOptimumBehavesAlike) {
  auto run = [](const char* damping, double eps_prime) {
    auto sim = load("", damping);
    return shear(sim, eps_prime / sim.time_scale().t0, static_cast<int>(0.01 / (0.3 * eps_prime)));
  };
  const History a = run("{model: OD, ratio: 0.02}", 1e-5);
  const History b = run("{model: OD, ratio: 0.04}", 5e-6);
  const History c = run("{model: OD, ratio: 0.02}", 5e-6);
  EXPECT_NEAR(b.mean_i_mom / a.mean_i_mom, 1.0, 0.10);
  EXPECT_NEAR(b.q_end / a.q_end, 1.0, 0.10);
  EXPECT_GT(std::fabs(c.mean_i_mom / a.mean_i_mom - 1.0), std::fabs(b.mean_i_mom / a.mean_i_mom - 1.0));
  std::printf("xi eps' 2e-7: I_mom %.4g / %.4g, q %.4g / %.4g Pa; half the product: I_mom %.4g, q %.4g Pa\n",
              a.mean_i_mom, b.mean_i_mom, a.q_end, b.q_end, c.mean_i_mom, c.q_end);
}
