// Axis stiffness of the packing for the servo (dem/axis_stiffness.h):
//   M_i = (1/V) sum_c d_i^2 (K_n n_i^2 + K_t (1 - n_i^2)),  K_n = 3/2 F_n / delta
// (eq. 115-116), K_t = 2(1-nu)/(2-nu) K_n (eq. 114). On two Hertz spheres
// pressed together along an axis and along a diagonal, M equals the closed
// form K_n = 2 E* sqrt(R* delta) (Hertz tangent stiffness); on a packing,
// the block-wise sum (contacts listed first, then summed) equals the plain
// loop over the list entries bit for bit; a run restored from a state has
// none until its first step, then the uninterrupted run's, bit for bit.
// After a measured step M comes from the contact sums of that evaluation:
// the same on one thread and on two, bit for bit, and the plain loop's value
// over that evaluation's contacts to 1e-12 (spheres and spheroids).
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>

#include "support/omp_threads.h"
#include "support/scenes.h"
#include "virtual_triaxial/dem/axis_stiffness.h"
#include "virtual_triaxial/dem/axis_stiffness_term.h"
#include "virtual_triaxial/dem/hertz_mindlin.h"
#include "virtual_triaxial/dem/simulation.h"

using namespace vt::dem;

namespace {

constexpr double kL = 0.05;  // cell edge [m]

/// Two spheres of radius r at rest, overlapping by delta along the unit
/// direction u (fractional offsets in a cubic cell of edge kL), forces evaluated.
Simulation pressed_pair(double r, double delta, const Vec3& u) {
  Particles p;
  p.add_sphere(0, r, 2650.0, {0.5, 0.5, 0.5});
  const double gap = (2 * r - delta) / kL;
  p.add_sphere(1, r, 2650.0, {0.5 + gap * u.x, 0.5 + gap * u.y, 0.5 + gap * u.z});
  Simulation sim(std::move(p), PeriodicCell(Vec3{kL, kL, kL}), vt::test::undamped(0.01));
  EXPECT_TRUE(sim.step(true));
  return sim;
}

/// 1500 spheres compressed isotropically for 300 steps (eps' = 1e-3): a
/// loaded contact network.
Simulation compressed_cloud() {
  vt::test::CloudScene sc = vt::test::polydisperse_cloud(1500, 0.6, 5);
  Simulation sim(std::move(sc.particles), sc.cell, vt::test::undamped(0.3));
  const double rate = 1e-3 / sim.time_scale().t0;
  sim.set_strain_rates({-rate, -rate, -rate});
  EXPECT_EQ(sim.run(300), 300) << sim.failure();
  return sim;
}

}  // namespace

TEST(AxisStiffness, TwoHertzSpheresGiveTheClosedForm) {
  const Material m = vt::test::test_material();
  const double r = 1e-3, delta = 2e-6;
  const double e_star = m.young / (2 * (1 - m.poisson * m.poisson));  // two equal materials
  const double kn = 2.0 * e_star * std::sqrt(0.5 * r * delta);  // R* = r/2
  const double kt = 2 * (1 - m.poisson) / (2 - m.poisson) * kn;
  const double d = 2 * r - delta, volume = kL * kL * kL;
  // along x: only M_x, from the normal stiffness
  const Vec3 mx = axis_stiffness(pressed_pair(r, delta, {1, 0, 0}));
  EXPECT_NEAR(mx.x, d * d * kn / volume, 1e-6 * d * d * kn / volume);
  EXPECT_EQ(mx.y, 0.0);
  EXPECT_EQ(mx.z, 0.0);
  // along the xy diagonal: n_x^2 = n_y^2 = 1/2, d_x^2 = d^2/2, half normal, half tangential
  const double s = std::sqrt(0.5);
  const Vec3 md = axis_stiffness(pressed_pair(r, delta, {s, s, 0}));
  const double expected = 0.5 * d * d * (0.5 * kn + 0.5 * kt) / volume;
  EXPECT_NEAR(md.x, expected, 1e-6 * expected);
  EXPECT_NEAR(md.y, expected, 1e-6 * expected);
  EXPECT_EQ(md.z, 0.0);
  // listed (inside the skin) but apart: nothing
  Simulation apart = pressed_pair(r, -0.01 * r, {1, 0, 0});
  ASSERT_EQ(apart.neighbor_list().offsets().back(), 1);
  const Vec3 none = axis_stiffness(apart);
  EXPECT_EQ(none.x + none.y + none.z, 0.0);
}

TEST(AxisStiffness, BlockwiseSumEqualsThePlainLoopBitForBit) {
  // a compressed cloud of 1500 spheres: many blocks of 256 entries, some in
  // contact; the reference is the loop axis_stiffness had before the blocks
  Simulation sim = compressed_cloud();
  const NeighborList& list = sim.neighbor_list();
  const PairData& pd = list.pairs();
  const auto& off = list.offsets();
  ASSERT_GT(off.back(), 3 * 1024);
  std::int64_t contacts = 0;
  const Material& mat = sim.settings().material;
  const double kt_ratio = 2.0 * (1.0 - mat.poisson) / (2.0 - mat.poisson);
  Vec3 plain{};
  for (std::size_t i = 0; i + 1 < off.size(); ++i)
    for (std::int32_t e = off[i]; e < off[i + 1]; ++e) {
      const double h = pd.half_overlap[e];
      if (h <= 0.0) continue;
      const Vec3 d = sim.cell().branch(sim.particles().frac[i], sim.particles().frac[pd.partner[e]]);
      const double dist = norm(d);
      if (dist <= 0.0) continue;
      const Vec3 n = (1.0 / dist) * d;
      const double kn = 1.5 * dot(pd.force[e], n) / (2.0 * h);
      const double kt = kt_ratio * kn;
      for (int a = 0; a < 3; ++a) plain[a] += d[a] * d[a] * (kn * n[a] * n[a] + kt * (1.0 - n[a] * n[a]));
    }
  for (std::int32_t e = 0; e < off.back(); ++e) contacts += pd.half_overlap[e] > 0.0 ? 1 : 0;
  ASSERT_GT(contacts, 500);
  plain = (1.0 / sim.cell().volume()) * plain;
  const Vec3 m = axis_stiffness_of_list(sim);
  EXPECT_EQ(m.x, plain.x);
  EXPECT_EQ(m.y, plain.y);
  EXPECT_EQ(m.z, plain.z);
}

TEST(AxisStiffness, ARestoredRunHasNoneUntilItsFirstStepThenTheSame) {
  // restored histories flag their entries in contact with half_overlap -1
  // until the next force evaluation (NeighborList::restore): no term yet;
  // after one step the restored run's stiffness is the uninterrupted run's
  Simulation sim = compressed_cloud();
  const SimulationState saved = sim.state();
  ASSERT_GT(saved.contacts.size(), 500u);
  Simulation restored(saved);
  const Vec3 none = axis_stiffness(restored);
  EXPECT_EQ(none.x, 0.0);
  EXPECT_EQ(none.y, 0.0);
  EXPECT_EQ(none.z, 0.0);
  ASSERT_TRUE(sim.step(false));
  ASSERT_TRUE(restored.step(false));
  const Vec3 a = axis_stiffness(sim), b = axis_stiffness(restored);
  EXPECT_GT(a.x, 0.0);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.z, b.z);
}

namespace {

using vt::test::RestoreThreads;

/// M after one measured step from `start` on `threads` threads: from the
/// contact sums (axis_stiffness) and by a plain loop over the list entries
/// with the branches at the positions of the evaluation (the list pass takes
/// them after the step's motion, one step on).
std::pair<Vec3, Vec3> measured_on(const SimulationState& start, int threads) {
  RestoreThreads restore;
  omp_set_num_threads(threads);
  Simulation sim(start);
  const std::vector<Vec3> frac = sim.particles().frac;
  const PeriodicCell cell = sim.cell();
  EXPECT_TRUE(sim.step(true)) << sim.failure();
  EXPECT_NE(sim.last_evaluation_sums(), nullptr);
  const NeighborList& list = sim.neighbor_list();
  const PairData& pd = list.pairs();
  const auto& off = list.offsets();
  const double kt_ratio = HertzMindlin(sim.settings().material).tangential_ratio();
  Vec3 plain{};
  for (std::size_t i = 0; i + 1 < off.size(); ++i)
    for (std::int32_t e = off[i]; e < off[i + 1]; ++e) {
      const AxisStiffnessTerm t =
          axis_stiffness_term(cell.branch(frac[i], frac[pd.partner[e]]), pd.force[e], pd.half_overlap[e], kt_ratio);
      if (!t.none) plain = plain + Vec3{t.d2.x * t.stiffness.x, t.d2.y * t.stiffness.y, t.d2.z * t.stiffness.z};
    }
  return {axis_stiffness(sim), (1.0 / cell.volume()) * plain};
}

/// The sums' M equals the plain loop's to 1e-12 (the order of the sums),
/// is positive, and is the same on one thread and on two, bit for bit.
void check_sums_against_plain(const SimulationState& start) {
  const auto [one, plain] = measured_on(start, 1);
  const auto [two, plain_two] = measured_on(start, 2);
  for (int a = 0; a < 3; ++a) {
    EXPECT_GT(one[a], 0.0) << "axis " << a;
    EXPECT_NEAR(one[a], plain[a], 1e-12 * plain[a]) << "axis " << a;
    EXPECT_EQ(one[a], two[a]) << "axis " << a;
  }
}

}  // namespace

TEST(AxisStiffness, AMeasuredStepGivesItFromTheContactSumsOnAnyThreads) {
  // 1500 spheres (3 chunks: a team of two splits them), loaded
  Simulation sim = compressed_cloud();
  check_sums_against_plain(sim.state());
  // an unmeasured step after it (not one that check_interval measures
  // anyway): the list pass again
  Simulation again(sim.state());
  ASSERT_TRUE(again.step(true));
  ASSERT_NE(again.steps() % again.settings().check_interval, 0);  // the next step's index
  ASSERT_TRUE(again.step(false));
  EXPECT_EQ(again.last_evaluation_sums(), nullptr);
  EXPECT_EQ(axis_stiffness(again).x, axis_stiffness_of_list(again).x);
}

TEST(AxisStiffness, SpheroidContactSumsMatchThePlainLoopOnAnyThreads) {
  // 1500 spheroids of aspect 1.2 compressed isotropically into contact
  vt::test::CloudScene sc = vt::test::spheroid_cloud(1500, 1.2, 0.6, 7);
  Simulation sim(std::move(sc.particles), sc.cell, vt::test::undamped(0.3));
  const double rate = 1e-3 / sim.time_scale().t0;
  sim.set_strain_rates({-rate, -rate, -rate});
  ASSERT_EQ(sim.run(700), 700) << sim.failure();
  ASSERT_GT(sim.measures().contacts, 300);
  check_sums_against_plain(sim.state());
}
