// Periodic tiling (dem/periodic_tiling.h): k copies of a prepared periodic
// sample are the same packing, so the tiled sample keeps the void ratio and
// contacts per particle of the original exactly, its stress tensor to
// round-off, and every copy of a particle feels the original's force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "virtual_triaxial/dem/periodic_tiling.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/io/sample_file.h"

namespace fs = std::filesystem;
using namespace vt;

namespace {

dem::SimulationState shipped(const char* name) {
  return io::read_sample((fs::path(VT_SOURCE_DIR) / "config/samples" / name).string());
}

void expect_same_state(const dem::SimulationState& original, int kx, int ky, int kz) {
  const std::size_t copies = static_cast<std::size_t>(kx * ky * kz);
  const dem::SimulationState tiled = dem::tile_periodic(original, kx, ky, kz);
  ASSERT_EQ(tiled.particles.size(), copies * original.particles.size());
  ASSERT_EQ(tiled.contacts.size(), copies * original.contacts.size());
  dem::Simulation a(original);
  dem::Simulation b(tiled);  // throws if a tiled contact were not within reach
  ASSERT_TRUE(a.step(true)) << a.failure();
  ASSERT_TRUE(b.step(true)) << b.failure();
  const dem::Measures ma = a.measures(), mb = b.measures();
  EXPECT_NEAR(mb.void_ratio, ma.void_ratio, 1e-12 * ma.void_ratio);
  EXPECT_EQ(mb.contacts, static_cast<std::int64_t>(copies) * ma.contacts);
  EXPECT_DOUBLE_EQ(mb.raw_coordination_number, ma.raw_coordination_number);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mb.stress(r, c), ma.stress(r, c), 1e-10 * ma.p) << r << c;
  EXPECT_NEAR(mb.coordination_number, ma.coordination_number, 1e-12);
  // Every copy of particle i feels the force of i (sums of the same terms,
  // possibly in another order; spheroid normals converge from the same warm
  // start to within the solver's tolerance): round-off of the largest
  // contact force.
  const std::size_t n = original.particles.size();
  double fmax = 0;
  const dem::PairData& pd = a.neighbor_list().pairs();
  for (std::size_t e = 0; e < pd.size(); ++e) fmax = std::max(fmax, dem::norm(pd.force[e]));
  double worst = 0;
  for (std::size_t k = 0; k < copies; ++k)
    for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, dem::norm(b.forces()[k * n + i] - a.forces()[i]));
  EXPECT_LT(worst, 1e-9 * fmax);
  EXPECT_GT(ma.contacts, 0);
}

}  // namespace

TEST(PeriodicTiling, DenseSphereSampleKeepsVoidRatioContactsAndStress) {
  expect_same_state(shipped("dense_1000.h5"), 2, 2, 2);
}

TEST(PeriodicTiling, UnequalFactorsAndSpheroids) {
  expect_same_state(shipped("dense_1000.h5"), 3, 1, 2);
  expect_same_state(shipped("dense_1000_spheroid.h5"), 1, 2, 1);
}

TEST(PeriodicTiling, IdsStayUniqueAndOrderedInContacts) {
  const dem::SimulationState t = dem::tile_periodic(shipped("dense_1000.h5"), 2, 1, 1);
  std::vector<std::int64_t> ids = t.particles.id;
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(std::adjacent_find(ids.begin(), ids.end()), ids.end());
  for (const dem::ContactHistory& c : t.contacts) EXPECT_LT(c.id_a, c.id_b);
  EXPECT_THROW(dem::tile_periodic(shipped("dense_1000.h5"), 0, 1, 1), std::invalid_argument);
}
