// A contact across every face, edge and corner of the periodic cell gives the
// same force as the same pair inside the cell.
#include <gtest/gtest.h>

#include <cmath>

#include "support/scenes.h"
#include "virtual_triaxial/dem/contact_forces.h"

using namespace vt::dem;

namespace {

struct PairForces {
  Vec3 f0, f1, t0, t1;
};

/// Pair with particle 0 at fractional s0, particle 1 at s0 + H^-1 d (wrapped),
/// relative velocity and spins so that the tangential spring is loaded.
PairForces pair_forces(const PeriodicCell& cell, const Vec3& s0, const Vec3& d) {
  Particles p;
  const Vec3 s1 = PeriodicCell::wrap(s0 + cell.h_inverse() * d);
  p.add_sphere(0, 1.0e-3, 2650, PeriodicCell::wrap(s0), {1e-3, -2e-3, 0.5e-3}, {3, -1, 2});
  p.add_sphere(1, 0.9e-3, 2650, s1, {-2e-3, 1e-3, 1e-3}, {-1, 2, 0.5});
  NeighborList list;
  list.set_skin(0.2e-3);
  list.build(p, cell);
  EXPECT_EQ(list.pairs().size(), 1u);
  HertzMindlin law(vt::test::test_material(0.5));
  ContactForces cf;
  std::vector<Vec3> f, t;
  for (int k = 0; k < 3; ++k) cf.compute(p, cell, list, law, 1e-7, false, f, t);
  return {f[0], f[1], t[0], t[1]};
}

void expect_same(const Vec3& a, const Vec3& b, double scale, const char* what) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-12 * scale) << what << " component " << k;
}

}  // namespace

TEST(PeriodicImages, EveryFaceEdgeAndCornerMatchesTheInteriorPair) {
  PeriodicCell cell(Vec3{12e-3, 10e-3, 14e-3});
  cell.set_strain_rates({-0.3, 0.1, 0.2});  // affine relative velocity enters the spring
  const Vec3 d{1.2e-3, -0.8e-3, 0.9e-3};     // |d| < R0 + R1: in contact
  ASSERT_LT(norm(d), 1.9e-3);
  const PairForces inside = pair_forces(cell, {0.5, 0.5, 0.5}, d);
  const double scale = norm(inside.f1);
  ASSERT_GT(scale, 0.0);
  expect_same(inside.f0, -inside.f1, scale, "action-reaction");
  int cases = 0;
  for (int ix = -1; ix <= 1; ++ix)
    for (int iy = -1; iy <= 1; ++iy)
      for (int iz = -1; iz <= 1; ++iz) {
        if (ix == 0 && iy == 0 && iz == 0) continue;
        // Put particle 0 just inside the face/edge/corner so that the branch
        // vector d crosses it.
        const double eps = 1e-5;
        const Vec3 s0{ix == 0 ? 0.5 : (ix > 0 ? 1 - eps : eps), iy == 0 ? 0.5 : (iy > 0 ? 1 - eps : eps),
                      iz == 0 ? 0.5 : (iz > 0 ? 1 - eps : eps)};
        const Vec3 dd{ix == 0 ? d.x : ix * std::fabs(d.x), iy == 0 ? d.y : iy * std::fabs(d.y),
                      iz == 0 ? d.z : iz * std::fabs(d.z)};
        const PairForces ref = pair_forces(cell, {0.5, 0.5, 0.5}, dd);
        const PairForces across = pair_forces(cell, s0, dd);
        expect_same(across.f0, ref.f0, scale, "force on 0");
        expect_same(across.f1, ref.f1, scale, "force on 1");
        expect_same(across.t0, ref.t0, scale * 1e-3, "torque on 0");
        expect_same(across.t1, ref.t1, scale * 1e-3, "torque on 1");
        expect_same(across.f0 + across.f1, Vec3{}, scale, "sum of forces");
        ++cases;
      }
  EXPECT_EQ(cases, 26);
}

TEST(PeriodicImages, TotalContactForceOfADensePackingIsZero) {
  vt::test::CloudScene sc = vt::test::polydisperse_cloud(300, 2.0, 7);
  SimulationSettings s = vt::test::undamped(0.3);
  s.damping = MassDamping(DampingModel::OD, 0.1);
  Simulation sim(std::move(sc.particles), sc.cell, s);
  // Compress until many contacts exist.
  sim.set_strain_rates(Vec3{-1, -1, -1} * (1e-3 / sim.time_scale().t0));
  int guard = 0;
  while (guard++ < 20000) {
    ASSERT_TRUE(sim.step(true)) << sim.failure();
    if (sim.measures().contacts > 450) break;
  }
  const Measures m = sim.measures();
  ASSERT_GT(m.contacts, 450);
  Vec3 total{};
  double sum_abs = 0;
  for (const Vec3& f : sim.forces()) {
    total += f;
    sum_abs += norm(f);
  }
  EXPECT_LT(norm(total), 1e-13 * sum_abs);
}
