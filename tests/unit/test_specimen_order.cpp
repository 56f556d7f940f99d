// Storage order of a new specimen (dem/spatial_sort.h, order_new_specimen):
// a generated specimen of more than 1536 particles starts in slab order,
// carrying every particle's data and its contacts with it; a smaller one
// keeps the generator's order; a sample file is loaded as stored, so a
// state saved mid-run continues bit for bit; triax_import sorts a LAMMPS
// packing it imports and, with --sort, re-stores a sample.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "support/cli.h"
#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/dem/periodic_tiling.h"
#include "virtual_triaxial/dem/spatial_sort.h"
#include "virtual_triaxial/io/lammps_data_file.h"
#include "virtual_triaxial/io/sample_file.h"
#include "virtual_triaxial/io/scene_builder.h"
#include "virtual_triaxial/io/scene_parser.h"

namespace fs = std::filesystem;
using namespace vt;

namespace {

std::string sample(const char* name) { return (fs::path(VT_SOURCE_DIR) / "config/samples" / name).string(); }

std::string read_text(const fs::path& p) {
  std::ifstream in(p.string());
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool same_order(const dem::Particles& a, const dem::Particles& b) {
  return a.size() == b.size() && std::memcmp(a.id.data(), b.id.data(), a.size() * sizeof(a.id[0])) == 0;
}

bool in_space_order(const dem::Particles& p, const dem::PeriodicCell& cell) {
  const std::vector<std::int32_t> order = dem::spatial_order(p, cell);
  for (std::size_t k = 0; k < order.size(); ++k)
    if (order[k] != static_cast<std::int32_t>(k)) return false;
  return true;
}

/// The shipped dense_4000.h5 stored in reverse order: not in space order.
dem::SimulationState reversed_dense_4000() {
  dem::SimulationState s = io::read_sample(sample("dense_4000.h5"));
  std::vector<std::int32_t> order(s.particles.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<std::int32_t>(order.size() - 1 - k);
  dem::permute(s.particles, order);
  return s;
}

}  // namespace

TEST(SpecimenOrder, SortsFromTheSizeWhereTwoThreadsAreUseful) {
  // two threads need 2 chunks of 512 each (ThreadGovernor::kMinChunksPerThread)
  EXPECT_EQ(dem::kSortFromParticles, 3u * dem::kChunkSize);
  EXPECT_FALSE(dem::sorts_new_specimen(1000));
  EXPECT_FALSE(dem::sorts_new_specimen(3 * dem::kChunkSize));      // 1536: 3 chunks
  EXPECT_TRUE(dem::sorts_new_specimen(3 * dem::kChunkSize + 1));   // 4 chunks
  EXPECT_TRUE(dem::sorts_new_specimen(100000));
}

TEST(SpecimenOrder, SortingCarriesEveryParticlesDataAndContacts) {
  const dem::SimulationState stored = reversed_dense_4000();
  const dem::PeriodicCell cell(stored.h, stored.h_reference);
  ASSERT_FALSE(in_space_order(stored.particles, cell));
  dem::SimulationState sorted = stored;
  dem::order_new_specimen(sorted);
  const dem::Particles &a = stored.particles, &b = sorted.particles;
  EXPECT_TRUE(in_space_order(b, cell));
  // exactly the order of spatial_order
  const std::vector<std::int32_t> order = dem::spatial_order(a, cell);
  for (std::size_t k = 0; k < b.size(); ++k) ASSERT_EQ(b.id[k], a.id[static_cast<std::size_t>(order[k])]);
  // every particle keeps its own data (looked up by id)
  std::map<std::int64_t, std::size_t> where;
  for (std::size_t i = 0; i < a.size(); ++i) where[a.id[i]] = i;
  ASSERT_EQ(where.size(), a.size());
  for (std::size_t k = 0; k < b.size(); ++k) {
    const std::size_t i = where.at(b.id[k]);
    ASSERT_EQ(std::memcmp(&b.frac[k], &a.frac[i], sizeof(dem::Vec3)), 0);
    ASSERT_EQ(std::memcmp(&b.velocity[k], &a.velocity[i], sizeof(dem::Vec3)), 0);
    ASSERT_EQ(b.radius[k], a.radius[i]);
    ASSERT_EQ(b.mass[k], a.mass[i]);
  }
  // contacts are keyed by ids: unchanged
  ASSERT_FALSE(stored.contacts.empty());
  ASSERT_EQ(sorted.contacts.size(), stored.contacts.size());
  EXPECT_EQ(std::memcmp(sorted.contacts.data(), stored.contacts.data(),
                        stored.contacts.size() * sizeof(stored.contacts[0])),
            0);
  // sorting a sorted specimen changes nothing
  dem::SimulationState again = sorted;
  dem::order_new_specimen(again);
  EXPECT_TRUE(same_order(again.particles, sorted.particles));
  // the same packing: the first step's mean stress agrees to round-off
  dem::Simulation s0(stored), s1(sorted);
  ASSERT_TRUE(s0.step(true));
  ASSERT_TRUE(s1.step(true));
  const double p0 = s0.measures().p, p1 = s1.measures().p;
  EXPECT_GT(p0, 5e4);
  EXPECT_NEAR(p1, p0, 1e-9 * p0);
  // the shipped 4000-particle samples are stored sorted (triax_import --sort)
  for (const char* name : {"dense_4000.h5", "loose_4000.h5"}) {
    const dem::SimulationState s = io::read_sample(sample(name));
    EXPECT_TRUE(in_space_order(s.particles, dem::PeriodicCell(s.h, s.h_reference))) << name;
  }
}

// The slab order's promise (spatial_sort.h): slabs across the cell's
// longest axis, and touching particles stored within two consecutive slabs
// of each other, except the pairs across the cell's periodic wrap across
// the slabs, so the loops stream through a window of a few slabs and no
// partner is a random jump in memory. On a Morton order this fails: pairs
// across its coarse bins' faces are stored thousands of particles apart.
TEST(SpecimenOrder, TouchingParticlesAreStoredWithinTwoSlabsOfEachOther) {
  // 3x2x2 copies: the cell is longest along s_1
  dem::SimulationState s = dem::tile_periodic(io::read_sample(sample("dense_1000.h5")), 3, 2, 2);
  dem::order_new_specimen(s);
  const dem::Particles& p = s.particles;
  const dem::PeriodicCell cell(s.h, s.h_reference);
  const std::size_t n = p.size();
  ASSERT_EQ(n, 12000u);
  ASSERT_TRUE(in_space_order(p, cell));
  const dem::SortGrid grid = dem::sort_grid(p, cell);
  ASSERT_EQ(grid.axes[0], 0) << "slabs across the longest axis";
  EXPECT_GT(grid.bins[0], grid.bins[1]);
  const int mid = grid.axes[1];
  const int slabs = grid.bins[0];
  ASSERT_GE(slabs, 8);
  std::vector<int> slab(n);
  std::vector<std::size_t> count(static_cast<std::size_t>(slabs), 0);
  for (std::size_t i = 0; i < n; ++i) {
    slab[i] = grid.bin(p.frac[i], 0);
    ++count[static_cast<std::size_t>(slab[i])];
  }
  // storage is by slab, each slab one contiguous run, and within a slab by
  // rows along the middle axis
  std::size_t out_of_order = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (slab[i - 1] > slab[i] || (slab[i - 1] == slab[i] && grid.bin(p.frac[i - 1], mid) > grid.bin(p.frac[i], mid)))
      ++out_of_order;
  EXPECT_EQ(out_of_order, 0u);
  std::size_t window = 0;  // the most particles in two consecutive slabs
  for (int l = 0; l + 1 < slabs; ++l) window = std::max(window, count[static_cast<std::size_t>(l)] + count[static_cast<std::size_t>(l + 1)]);
  EXPECT_LT(window, 3 * n / static_cast<std::size_t>(slabs));  // slabs hold about N / slabs each
  std::size_t touching = 0, across_wrap = 0, farthest = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const double reach = p.radius[i] + p.radius[j];
      if (norm2(cell.branch(p.frac[i], p.frac[j])) >= reach * reach) continue;
      ++touching;
      if (std::abs(slab[i] - slab[j]) > 1) {
        ++across_wrap;
        EXPECT_TRUE(std::min(slab[i], slab[j]) == 0 && std::max(slab[i], slab[j]) == slabs - 1)
            << "particles " << i << " and " << j << " touch " << std::abs(slab[i] - slab[j]) << " slabs apart";
        continue;
      }
      farthest = std::max(farthest, j - i);
    }
  EXPECT_GT(touching, 2 * n);  // a dense packing: about 2.6 touching pairs per particle
  EXPECT_LT(across_wrap, touching / 4);
  EXPECT_LT(farthest, window) << "touching particles stored " << farthest << " apart";
}

// The slab axis has the most bins; equal counts keep s_3, s_2, s_1 (the
// 10^5 bench tile 5x5x4 has 40 x 40 x 32 bins: slabs across s_2, rows
// along s_1; the 1000-particle sample, a cube, keeps s_3, s_2, s_1).
TEST(SpecimenOrder, TheSlabAxisHasTheMostBinsAndTiesKeepTheLastAxis) {
  const dem::SimulationState one = io::read_sample(sample("dense_1000.h5"));
  const dem::SimulationState big = dem::tile_periodic(one, 5, 5, 4);
  const dem::SortGrid g = dem::sort_grid(big.particles, dem::PeriodicCell(big.h, big.h_reference));
  const auto axes = [](const dem::SortGrid& grid) {
    return std::vector<int>{grid.axes[0], grid.axes[1], grid.axes[2]};
  };
  EXPECT_EQ(g.bins[0], g.bins[1]);
  EXPECT_GT(g.bins[0], g.bins[2]);
  EXPECT_EQ(axes(g), (std::vector<int>{1, 0, 2}));
  const dem::SortGrid c = dem::sort_grid(one.particles, dem::PeriodicCell(one.h, one.h_reference));
  ASSERT_EQ(c.bins[0], c.bins[1]);
  ASSERT_EQ(c.bins[1], c.bins[2]);
  EXPECT_EQ(axes(c), (std::vector<int>{2, 1, 0}));
  // bins one largest diameter wide at least: touching particles are at most one bin apart
  const double width = 2.0 * big.particles.max_bounding_radius();
  const dem::Vec3 h = dem::PeriodicCell(big.h, big.h_reference).heights();
  for (int a = 0; a < 3; ++a) EXPECT_GE(h[a] / g.bins[a], width) << "axis " << a;
}

TEST(SpecimenOrder, ASampleFileLoadsAsStoredAndAMidRunStateContinuesBitForBit) {
  // a 4000-particle state in an order that is not the space order, saved as
  // a sample file and run through the scene builder (as triax_run and the rig do)
  const fs::path dir = fs::temp_directory_path() / ("vt_specimen_order_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string start = (dir / "start.h5").string(), mid = (dir / "mid.h5").string();
  const dem::SimulationState reversed = reversed_dense_4000();
  io::write_sample(start, reversed, io::SampleMetadata{});
  const std::string protocol = read_text(fs::path(VT_SOURCE_DIR) / "config/protocols/drained_100kPa_4000.yaml");
  const std::string key = "sample_file: ../samples/dense_4000.h5";
  ASSERT_NE(protocol.find(key), std::string::npos);
  const auto scene_from = [&](const std::string& file) {
    std::string text = protocol;
    text.replace(text.find(key), key.size(), "sample_file: " + file);
    return io::parse_scene(text, (dir / "scene.yaml").string());
  };
  // loaded as stored
  dem::Simulation whole = io::build_simulation(scene_from(start));
  EXPECT_TRUE(same_order(whole.particles(), reversed.particles));
  // 60 steps at once against 30, save, load, 30
  const double rate = 1e-4 / whole.time_scale().t0;
  whole.set_strain_rates({0.5 * rate, 0.5 * rate, -rate});
  ASSERT_EQ(whole.run(60), 60);
  dem::Simulation first = io::build_simulation(scene_from(start));
  first.set_strain_rates({0.5 * rate, 0.5 * rate, -rate});
  ASSERT_EQ(first.run(30), 30);
  io::write_sample(mid, first.state(), io::SampleMetadata{});
  dem::Simulation second = io::build_simulation(scene_from(mid));
  ASSERT_EQ(second.run(30), 30);
  const dem::Particles &a = whole.particles(), &b = second.particles();
  ASSERT_TRUE(same_order(a, b));
  EXPECT_EQ(std::memcmp(a.frac.data(), b.frac.data(), a.size() * sizeof(dem::Vec3)), 0);
  EXPECT_EQ(std::memcmp(a.velocity.data(), b.velocity.data(), a.size() * sizeof(dem::Vec3)), 0);
  fs::remove_all(dir);
}

TEST(SpecimenOrder, AGeneratedCloudStartsSortedWhenLarge) {
  // the default scene's cloud (config/scenes/default.yaml) at 1000 and 2000 particles
  const std::string yaml = read_text(fs::path(VT_SOURCE_DIR) / "config/scenes/default.yaml");
  const std::size_t at = yaml.find("count: 1000");
  ASSERT_NE(at, std::string::npos);
  const dem::Simulation small = io::build_simulation(io::parse_scene(yaml));
  EXPECT_EQ(small.particles().size(), 1000u);
  EXPECT_FALSE(in_space_order(small.particles(), small.cell()));  // the generator's order (decreasing radius)
  std::string big_yaml = yaml;
  big_yaml.replace(at, 11, "count: 2000");
  const dem::Simulation big = io::build_simulation(io::parse_scene(big_yaml));
  EXPECT_EQ(big.particles().size(), 2000u);
  EXPECT_TRUE(in_space_order(big.particles(), big.cell()));
}

TEST(SpecimenOrder, AParticleListStartsSortedWhenLargeWithItsIds) {
  // k^3 spheres on a grid, listed in a scrambled order (grid cell (37 i) mod n)
  const auto list_scene = [](int k) {
    const int n = k * k * k;
    const double a = 3e-3;
    std::ostringstream y;
    y.precision(17);
    y << "particles:\n  list:\n";
    for (int i = 0; i < n; ++i) {
      const int c = static_cast<int>((37LL * i) % n);
      y << "    - {id: " << i << ", radius: 1.0e-3, position: [" << a * (c % k) << ", " << a * ((c / k) % k) << ", "
        << a * (c / (k * k)) << "]}\n";
    }
    y << "cell:\n  lengths: [" << a * k << ", " << a * k << ", " << a * k << "]\n"
      << "stages:\n  - {type: relax, stop: {steps: 10}}\n";
    return io::parse_scene(y.str());
  };
  const dem::Simulation small = io::build_simulation(list_scene(10));  // 1000: as listed
  ASSERT_EQ(small.particles().size(), 1000u);
  for (std::size_t i = 0; i < 1000; ++i) ASSERT_EQ(small.particles().id[i], static_cast<std::int64_t>(i));
  EXPECT_FALSE(in_space_order(small.particles(), small.cell()));
  const dem::Simulation big = io::build_simulation(list_scene(12));  // 1728: sorted
  const dem::Particles& p = big.particles();
  ASSERT_EQ(p.size(), 1728u);
  EXPECT_TRUE(in_space_order(p, big.cell()));
  std::vector<char> seen(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    ASSERT_GE(p.id[i], 0);
    ASSERT_LT(p.id[i], 1728);
    seen[static_cast<std::size_t>(p.id[i])] = 1;
  }
  for (char s : seen) ASSERT_TRUE(s);  // every listed id, once
}

TEST(SpecimenOrder, TriaxImportSortsImportsAndReStoresSamples) {
  const fs::path dir = vt::test::scratch_dir("specimen_order_import");
  const auto import = [&](const std::string& args) { return vt::test::run_program("triax_import", args, dir); };
  const dem::SimulationState reversed = reversed_dense_4000();
  io::SampleMetadata meta;
  meta.created_by = "test: dense_4000 reversed";
  const fs::path in = dir / "reversed.h5", out = dir / "sorted.h5", again = dir / "again.h5";
  io::write_sample(in.string(), reversed, meta);
  // --sort: slab order, every particle's data by id, contacts and metadata kept
  vt::test::CliRun r = import("--sort " + in.string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  io::SampleMetadata got;
  const dem::SimulationState sorted = io::read_sample(out.string(), &got);
  EXPECT_EQ(got.created_by, meta.created_by);
  EXPECT_TRUE(in_space_order(sorted.particles, dem::PeriodicCell(sorted.h, sorted.h_reference)));
  dem::SimulationState expected = reversed;
  dem::spatial_sort(expected);
  ASSERT_TRUE(same_order(sorted.particles, expected.particles));
  EXPECT_EQ(std::memcmp(sorted.particles.frac.data(), expected.particles.frac.data(),
                        expected.particles.size() * sizeof(dem::Vec3)),
            0);
  ASSERT_EQ(sorted.contacts.size(), reversed.contacts.size());
  EXPECT_EQ(std::memcmp(sorted.contacts.data(), reversed.contacts.data(),
                        reversed.contacts.size() * sizeof(reversed.contacts[0])),
            0);
  // sorting the sorted file gives the same bytes
  r = import("--sort " + out.string() + " --out " + again.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(vt::test::slurp(out), vt::test::slurp(again));
  // --lammps: a 4000-particle packing is stored sorted
  const fs::path data = dir / "reversed.data", imported = dir / "imported.h5";
  io::write_lammps_data(data.string(), reversed);
  r = import("--lammps " + data.string() + " --out " + imported.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const dem::SimulationState im = io::read_sample(imported.string());
  ASSERT_EQ(im.particles.size(), 4000u);
  EXPECT_TRUE(in_space_order(im.particles, dem::PeriodicCell(im.h, im.h_reference)));
  // bad input: two modes, a missing file
  r = import("--sort " + in.string() + " --lammps " + data.string() + " --out " + again.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("exactly one of"), std::string::npos) << r.err;
  r = import("--sort " + (dir / "missing.h5").string() + " --out " + again.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("missing.h5"), std::string::npos) << r.err;
}
