#include "support/spheroid_scenes.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "support/scenes.h"
#include "virtual_triaxial/dem/rigid_rotation.h"

namespace vt::test {

using namespace dem;

namespace {
constexpr std::int64_t kPackingSteps = 10000;  // compression steps at most (loaded_spheroid_packing)
}  // namespace

void add_at(PairScene& s, std::int64_t id, double a, double b, const Quaternion& q, const Vec3& x, const Vec3& v,
            const Vec3& w) {
  s.p.add_spheroid(id, a, b, 2650.0, s.cell.h_inverse() * x, q, v, w);
}

Quaternion axis_rotation(const Vec3& u, double phi) { return axis_angle((1.0 / norm(u)) * u, phi); }

dem::SimulationState dense_spheroid_gas(double ct) {
  CloudScene sc = spheroid_cloud(200, 1.2, 1.6, 3);
  SimulationSettings s = undamped(ct, 0.0);
  s.damping = MassDamping(DampingModel::ND, 0.1);
  Simulation prep(std::move(sc.particles), sc.cell, s);
  prep.set_strain_rates(Vec3{-1, -1, -1} * (3e-4 / prep.time_scale().t0));
  while (prep.particles().solid_volume() * 2.6 < prep.cell().volume()) EXPECT_EQ(prep.run(10), 10);
  SimulationState st = prep.state();
  randomize_velocities(st.particles, 10.0, 2000.0, 11);
  st.velocity_gradient = Mat3{};
  st.settings.damping = MassDamping(DampingModel::OD, 0.0);
  st.settings.check_interval = 1000000;
  st.energy = EnergyBudget{};
  return st;
}

dem::SimulationState loaded_spheroid_packing() {
  CloudScene sc = spheroid_cloud(300, 1.2, 1.8, 5);
  SimulationSettings s = undamped(0.3, 0.5);
  s.damping = MassDamping(DampingModel::ND, 0.1);
  Simulation sim(std::move(sc.particles), sc.cell, s);
  sim.set_strain_rates(Vec3{-1, -1, -1} * (3e-4 / sim.time_scale().t0));
  // compress until the contact network holds 1.3 contacts per particle
  std::int64_t k = 0, contacts = 0;
  for (; k < kPackingSteps && contacts < 390; k += 100) {
    EXPECT_EQ(sim.run(99), 99) << sim.failure();
    EXPECT_TRUE(sim.step(true)) << sim.failure();
    contacts = sim.measures().contacts;
  }
  std::printf("[ packing ] %lld steps, %lld contacts, e = %.3f, p = %.3g Pa\n", static_cast<long long>(k),
              static_cast<long long>(contacts), sim.measures().void_ratio, sim.current_mean_stress());
  const double r = 2e-4 / sim.time_scale().t0;
  sim.set_strain_rates({0.5 * r, 0.5 * r, -r});
  return sim.state();
}

}  // namespace vt::test
