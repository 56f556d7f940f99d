// Periodic tiling (dem/periodic_tiling.h): k copies of a prepared periodic
// sample are the same packing, so the tiled sample keeps the void ratio and
// contacts per particle of the original exactly, its stress tensor to
// round-off, and every copy of a particle feels the original's force.
// The tools' tiling argument (parse_tile_factors) and triax_import --tile,
// which stores such copies in slab order as a sample file.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

#include "support/cli.h"
#include "virtual_triaxial/dem/periodic_tiling.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/dem/spatial_sort.h"
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

TEST(PeriodicTiling, TileArgumentTakesKOrKxKyKzInRange) {
  using Factors = std::optional<std::array<int, 3>>;
  EXPECT_EQ(dem::parse_tile_factors("3x2x2"), (Factors{{3, 2, 2}}));
  EXPECT_EQ(dem::parse_tile_factors("4"), (Factors{{4, 4, 4}}));
  EXPECT_EQ(dem::parse_tile_factors("1x100x1"), (Factors{{1, 100, 1}}));
  for (const char* bad : {"", "x", "0", "3x0x2", "3x2", "3x2x2x", "3x2x2 ", " 3x2x2", "3x 2x2", "+4", "101",
                          "2x-1x2", "2y2y2", "4k", "4294967297", "4294967298x1x1"})
    EXPECT_EQ(dem::parse_tile_factors(bad), std::nullopt) << "'" << bad << "'";
}

TEST(PeriodicTiling, RefusesMoreParticlesThanTheCoreIndexes) {
  // 4000 x 100^3 = 4e9 > 2^31 - 1: refused before anything is allocated
  try {
    dem::tile_periodic(shipped("dense_4000.h5"), dem::kTileFactorMax, dem::kTileFactorMax, dem::kTileFactorMax);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("2^31 - 1 particles"), std::string::npos) << e.what();
  }
}

// triax_import --tile: the stored sample is tile_periodic's state in slab
// order, the same bits (positions, contact histories), and keeps the source's
// metadata but for who made it and the description (which names the
// source); bad factors exit 2 naming the flag. Unequal factors, so that
// axes taken in another order fail.
TEST(PeriodicTiling, TriaxImportTileStoresSlabOrderedCopies) {
  const fs::path dir = vt::test::scratch_dir("periodic_tiling_import");
  const std::string in = (fs::path(VT_SOURCE_DIR) / "config/samples/dense_1000.h5").string();
  const fs::path out = dir / "tiled.h5";
  vt::test::CliRun r = vt::test::run_program("triax_import", "--tile " + in + " --factors 3x1x2 --out " + out.string(), dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("particles: 6000"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("tile: 3x1x2"), std::string::npos) << r.out;
  io::SampleMetadata source, got;
  const dem::SimulationState original = io::read_sample(in, &source);
  const dem::SimulationState stored = io::read_sample(out.string(), &got);
  dem::SimulationState expected = dem::tile_periodic(original, 3, 1, 2);
  dem::spatial_sort(expected);  // 6000 particles: a new specimen is sorted
  ASSERT_EQ(stored.particles.size(), expected.particles.size());
  EXPECT_EQ(stored.particles.id, expected.particles.id);
  EXPECT_EQ(std::memcmp(stored.particles.frac.data(), expected.particles.frac.data(),
                        expected.particles.size() * sizeof(dem::Vec3)),
            0);
  ASSERT_EQ(stored.contacts.size(), expected.contacts.size());
  for (std::size_t k = 0; k < expected.contacts.size(); ++k) {
    ASSERT_EQ(stored.contacts[k].id_a, expected.contacts[k].id_a) << k;
    ASSERT_EQ(stored.contacts[k].id_b, expected.contacts[k].id_b) << k;
    ASSERT_EQ(std::memcmp(&stored.contacts[k].spring, &expected.contacts[k].spring, sizeof(dem::Vec3)), 0) << k;
  }
  for (int r2 = 0; r2 < 3; ++r2)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(stored.h.m[r2][c], expected.h.m[r2][c]) << r2 << c;
  EXPECT_EQ(got.seed, source.seed);
  EXPECT_EQ(got.software_version, source.software_version);
  EXPECT_NE(got.created_by.find("--factors 3x1x2"), std::string::npos) << got.created_by;
  EXPECT_NE(got.description.find("periodic copies 3x1x2 of " + in), std::string::npos) << got.description;
  EXPECT_NE(got.description.find(source.description), std::string::npos) << got.description;
  // bad input
  r = vt::test::run_program("triax_import", "--tile " + in + " --factors 2x0x2 --out " + out.string(), dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--factors needs K or KxKyKz"), std::string::npos) << r.err;
  r = vt::test::run_program("triax_import", "--tile " + in + " --out " + out.string(), dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--tile needs it"), std::string::npos) << r.err;
  r = vt::test::run_program("triax_import", "--tile " + in + " --out " + out.string() + " --factors", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--factors needs K or KxKyKz"), std::string::npos) << r.err;
}
