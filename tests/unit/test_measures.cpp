// Hand-built configurations with known answers for stress, p, q, phi, void
// ratio, UFR, I_uf, moment index and coordination number.
#include <gtest/gtest.h>

#include <cmath>

#include "support/scenes.h"
#include "virtual_triaxial/dem/simulation.h"

using namespace vt::dem;

namespace {

constexpr double kR = 1e-3;
constexpr int kN = 4;  // 4 x 4 x 4 simple cubic lattice

/// Simple cubic lattice with spacings a = 2R - delta per axis; `skip` removes
/// one particle (index) when >= 0.
Simulation lattice(const Vec3& delta, int skip = -1, double friction = 0.5) {
  const Vec3 a{2 * kR - delta.x, 2 * kR - delta.y, 2 * kR - delta.z};
  PeriodicCell cell(Vec3{kN * a.x, kN * a.y, kN * a.z});
  Particles p;
  int id = 0;
  for (int k = 0; k < kN; ++k)
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i, ++id) {
        if (id == skip) continue;
        p.add_sphere(id, kR, 2650, {(i + 0.5) / kN, (j + 0.5) / kN, (k + 0.5) / kN});
      }
  SimulationSettings s = vt::test::undamped(0.1, friction);
  return Simulation(std::move(p), cell, s);
}

double hertz(double delta) {
  HertzMindlin law(vt::test::test_material());
  return law.normal_force(delta, 0.5 * kR);
}

}  // namespace

TEST(Measures, LatticeStressVoidRatioAndCoordination) {
  const Vec3 delta{4e-6, 2e-6, 1e-6};
  Simulation sim = lattice(delta);
  ASSERT_TRUE(sim.step(true));
  const Measures m = sim.measures();
  const Vec3 a{2 * kR - delta.x, 2 * kR - delta.y, 2 * kR - delta.z};
  // sigma_xx = F(delta_x) / (a_y a_z), compression positive
  const double sxx = hertz(delta.x) / (a.y * a.z), syy = hertz(delta.y) / (a.x * a.z),
               szz = hertz(delta.z) / (a.x * a.y);
  EXPECT_NEAR(m.stress(0, 0) / sxx, 1.0, 1e-12);
  EXPECT_NEAR(m.stress(1, 1) / syy, 1.0, 1e-12);
  EXPECT_NEAR(m.stress(2, 2) / szz, 1.0, 1e-12);
  EXPECT_NEAR(m.stress(0, 1), 0.0, 1e-12 * sxx);
  EXPECT_NEAR(m.p / ((sxx + syy + szz) / 3), 1.0, 1e-12);
  // axial = z; q = s_zz - min(s_xx, s_yy)
  EXPECT_NEAR(m.q, szz - std::min(sxx, syy), 1e-9 * sxx);
  EXPECT_NEAR(m.phi, std::asin((sxx - szz) / (sxx + szz)), 1e-12);
  EXPECT_NEAR(m.principal_stress.x / sxx, 1.0, 1e-12);
  EXPECT_NEAR(m.principal_stress.z / szz, 1.0, 1e-12);
  const double v_cell = kN * kN * kN * a.x * a.y * a.z;
  EXPECT_NEAR(m.void_ratio, v_cell / (kN * kN * kN * sphere_volume(kR)) - 1.0, 1e-12);
  EXPECT_EQ(m.contacts, 3 * kN * kN * kN);
  EXPECT_DOUBLE_EQ(m.coordination_number, 6.0);
  EXPECT_DOUBLE_EQ(m.idle_mass_fraction, 0.0);
  // Balanced lattice: no unbalanced force or moment.
  EXPECT_LT(m.ufr, 1e-12);
  EXPECT_LT(m.iuf, 1e-12);
  EXPECT_LT(m.moment_index, 1e-12);
  // Strain is zero at the start; elastic energy = sum 2/5 F delta.
  EXPECT_NEAR(m.energy.elastic, kN * kN * kN * 0.4 * (hertz(delta.x) * delta.x + hertz(delta.y) * delta.y +
                                                      hertz(delta.z) * delta.z),
              1e-12 * m.energy.elastic);
}

TEST(Measures, VacancyGivesKnownUnbalancedForceIndices) {
  const double d = 3e-6;
  Simulation sim = lattice({d, d, d}, /*skip=*/21);
  ASSERT_TRUE(sim.step(true));
  const Measures m = sim.measures();
  // 63 particles; the 6 neighbours of the vacancy each miss one contact and
  // carry an unbalanced force F; 3*64 - 6 = 186 contacts, all of size F.
  EXPECT_EQ(m.contacts, 186);
  EXPECT_NEAR(m.ufr, (6.0 / 63.0) / 1.0, 1e-12);
  EXPECT_NEAR(m.iuf, std::sqrt(6.0 / 63.0), 1e-12);
}

TEST(Measures, TangentialSpringGivesKnownMomentIndex) {
  const double d = 3e-6;
  Simulation base = lattice({d, d, d}, -1, 10.0);
  // Load one x-contact (particles 0 and 1) with a tangential force T along y.
  SimulationState st = base.state();
  const double t = 0.2 * hertz(d);
  st.contacts.push_back({0, 1, {0, t, 0}});
  Simulation sim(st);
  ASSERT_TRUE(sim.step(true));
  const Measures m = sim.measures();
  const double lever = kR - 0.5 * d;
  const double s = hertz(d) / ((2 * kR - d) * (2 * kR - d));  // isotropic stress
  const double v_cell = std::pow(kN * (2 * kR - d), 3);
  // symmetrised shear stress from the one tangential force: a T / (2 V)
  const double sxy = (2 * kR - d) * t / (2 * v_cell);
  const double oct = std::sqrt(3 * s * s + 2 * sxy * sxy) / std::sqrt(3.0);
  EXPECT_NEAR(m.moment_index, 2 * lever * t / (v_cell * oct), 1e-9 * m.moment_index);
  // The tangential force also unbalances particles 0 and 1 by T each.
  EXPECT_NEAR(m.ufr, (2 * t / 64.0) / ((191 * hertz(d) + std::hypot(hertz(d), t)) / 192.0), 1e-9);
}

TEST(Measures, IterativeIdleRemoval) {
  // K4 (0..3, each 3 contacts) + 4 linked to 0, 1, 5 + 5 linked to 4, 6 + 6
  // linked to 5. Pass 1 removes 5 and 6, which leaves 4 with 2 contacts;
  // pass 2 removes 4. Remaining: K4, 6 contacts, Z = 3.
  std::vector<std::pair<std::int32_t, std::int32_t>> c = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3},
                                                          {4, 0}, {4, 1}, {4, 5}, {5, 6}};
  std::vector<double> mass = {1, 1, 1, 1, 2, 1, 1};
  const Coordination r = mechanical_coordination(7, c, mass);
  EXPECT_EQ(r.active_particles, 4);
  EXPECT_EQ(r.active_contacts, 6);
  EXPECT_DOUBLE_EQ(r.mechanical, 3.0);
  EXPECT_DOUBLE_EQ(r.idle_mass_fraction, 4.0 / 8.0);
  // A chain of pendants collapses completely.
  const Coordination none = mechanical_coordination(3, {{0, 1}, {1, 2}}, {1, 1, 1});
  EXPECT_EQ(none.active_particles, 0);
  EXPECT_DOUBLE_EQ(none.mechanical, 0.0);
  EXPECT_DOUBLE_EQ(none.idle_mass_fraction, 1.0);
}

// The idle-particle removal of section 4.5 defined literally (sweep: mark
// every particle with < 3 live contacts idle, kill their contacts, repeat
// until nothing changes) against the library's one-pass peeling, on random
// contact graphs around the threshold (mean degree 2-6): same active set,
// same active contacts, same idle mass, exactly.
TEST(Measures, PeelingEqualsTheIterativeSweepDefinition) {
  std::uint64_t state = 12345;
  auto next = [&]() {  // xorshift64*, deterministic
    state ^= state >> 12;
    state ^= state << 25;
    state ^= state >> 27;
    return state * 2685821657736338717ULL;
  };
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t n = 5 + next() % 200;
    const std::size_t nc = n * (1 + next() % 3);
    std::vector<std::pair<std::int32_t, std::int32_t>> contacts;
    for (std::size_t k = 0; k < nc; ++k) {
      const auto a = static_cast<std::int32_t>(next() % n), b = static_cast<std::int32_t>(next() % n);
      if (a != b) contacts.emplace_back(a, b);
    }
    std::vector<double> mass(n);
    for (double& m : mass) m = 1.0 + static_cast<double>(next() % 1000) / 100.0;
    // Reference: the sweep.
    std::vector<int> degree(n, 0);
    for (const auto& c : contacts) ++degree[static_cast<std::size_t>(c.first)], ++degree[static_cast<std::size_t>(c.second)];
    std::vector<char> idle(n, 0), alive(contacts.size(), 1);
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t i = 0; i < n; ++i)
        if (!idle[i] && degree[i] < 3) idle[i] = 1, changed = true;
      for (std::size_t k = 0; k < contacts.size(); ++k) {
        const auto a = static_cast<std::size_t>(contacts[k].first), b = static_cast<std::size_t>(contacts[k].second);
        if (alive[k] && (idle[a] || idle[b])) alive[k] = 0, --degree[a], --degree[b];
      }
    }
    std::int64_t active = 0, live = 0;
    double idle_mass = 0, total = 0;
    for (std::size_t i = 0; i < n; ++i) {
      total += mass[i];
      if (idle[i]) idle_mass += mass[i];
      else ++active;
    }
    for (char a : alive) live += a;
    const Coordination c = mechanical_coordination(n, contacts, mass);
    ASSERT_EQ(c.active_particles, active) << "trial " << trial;
    ASSERT_EQ(c.active_contacts, live) << "trial " << trial;
    ASSERT_EQ(c.idle_mass_fraction, idle_mass / total) << "trial " << trial;
  }
}
