// Storage order of a new specimen (dem/spatial_sort.h, order_new_specimen):
// a specimen large enough for two threads (more than 1536 particles) starts
// its run in Morton order, carrying every particle's data and its contacts
// with it; a smaller one keeps its stored order bit for bit; a resumed run
// is never re-sorted (the order is part of the state it continues).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/dem/spatial_sort.h"
#include "virtual_triaxial/io/sample_file.h"
#include "virtual_triaxial/io/scene_builder.h"
#include "virtual_triaxial/io/scene_parser.h"

namespace fs = std::filesystem;
using namespace vt;

namespace {

std::string sample(const char* name) { return (fs::path(VT_SOURCE_DIR) / "config/samples" / name).string(); }

/// A shipped protocol's scene.
io::SceneConfig shipped_protocol(const char* name) {
  return io::load_scene((fs::path(VT_SOURCE_DIR) / "config/protocols" / name).string());
}

bool same_order(const dem::Particles& a, const dem::Particles& b) {
  return a.size() == b.size() && std::memcmp(a.id.data(), b.id.data(), a.size() * sizeof(a.id[0])) == 0;
}

}  // namespace

TEST(SpecimenOrder, SortsFromTheSizeWhereTwoThreadsAreUseful) {
  // two threads need 2 chunks of 512 each (ThreadGovernor::kMinChunksPerThread)
  EXPECT_FALSE(dem::sorts_new_specimen(1000));
  EXPECT_FALSE(dem::sorts_new_specimen(3 * dem::kChunkSize));      // 1536: 3 chunks
  EXPECT_TRUE(dem::sorts_new_specimen(3 * dem::kChunkSize + 1));   // 4 chunks
  EXPECT_TRUE(dem::sorts_new_specimen(100000));
}

TEST(SpecimenOrder, ALargeSampleStartsInMortonOrderWithItsDataAndContacts) {
  const dem::SimulationState stored = io::read_sample(sample("dense_4000.h5"));
  ASSERT_EQ(stored.particles.size(), 4000u);
  dem::SimulationState sorted = stored;
  dem::order_new_specimen(sorted);
  const dem::Particles &a = stored.particles, &b = sorted.particles;
  ASSERT_FALSE(same_order(a, b));  // the shipped sample is not stored in space order
  // exactly the order of spatial_order
  const std::vector<std::int32_t> order = dem::spatial_order(a, dem::PeriodicCell(stored.h, stored.h_reference));
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
  ASSERT_EQ(sorted.contacts.size(), stored.contacts.size());
  ASSERT_FALSE(stored.contacts.empty());
  EXPECT_EQ(std::memcmp(sorted.contacts.data(), stored.contacts.data(),
                        stored.contacts.size() * sizeof(stored.contacts[0])),
            0);
  // sorting a sorted specimen changes nothing
  dem::SimulationState again = sorted;
  dem::order_new_specimen(again);
  EXPECT_TRUE(same_order(again.particles, sorted.particles));
  // the same with the same contacts: the stress of the first step agrees to round-off
  dem::Simulation s0(stored), s1(sorted);
  ASSERT_TRUE(s0.step(true));
  ASSERT_TRUE(s1.step(true));
  const double p0 = s0.measures().p, p1 = s1.measures().p;
  EXPECT_GT(p0, 5e4);
  EXPECT_NEAR(p1, p0, 1e-9 * p0);
}

TEST(SpecimenOrder, RunsStartSortedOnlyWhenLargeAndResumesKeepTheirOrder) {
  // a run from a 4000-particle sample (dense_4000.h5) starts in the sorted order ...
  dem::SimulationState expected = io::read_sample(sample("dense_4000.h5"));
  dem::spatial_sort(expected);
  const dem::Simulation big = io::build_simulation(shipped_protocol("drained_100kPa_4000.yaml"));
  EXPECT_TRUE(same_order(big.particles(), expected.particles));
  // ... one from a 1000-particle sample (dense_1000.h5) in the stored order
  const dem::SimulationState small_stored = io::read_sample(sample("dense_1000.h5"));
  const dem::Simulation small = io::build_simulation(shipped_protocol("drained_100kPa.yaml"));
  EXPECT_TRUE(same_order(small.particles(), small_stored.particles));
  dem::SimulationState small_sorted = small_stored;
  dem::spatial_sort(small_sorted);
  EXPECT_FALSE(same_order(small.particles(), small_sorted.particles));  // the test can tell
  // a state continued as it is (resume, checkpoint) keeps its order, even
  // after the cell has deformed (which would move particles between bins)
  dem::Simulation run = io::build_simulation(shipped_protocol("drained_100kPa_4000.yaml"));
  run.set_strain_rates({0.0, 0.0, -2e-3 / run.time_scale().t0});
  ASSERT_EQ(run.run(50), 50);
  const dem::SimulationState mid = run.state();
  const dem::Simulation resumed(mid);
  EXPECT_TRUE(same_order(resumed.particles(), mid.particles));
}

TEST(SpecimenOrder, AGeneratedCloudStartsSortedWhenLarge) {
  // the default scene's cloud (config/scenes/default.yaml) at 1000 and 2000 particles
  std::string yaml;
  {
    std::ifstream in((fs::path(VT_SOURCE_DIR) / "config/scenes/default.yaml").string());
    std::stringstream ss;
    ss << in.rdbuf();
    yaml = ss.str();
  }
  const std::size_t at = yaml.find("count: 1000");
  ASSERT_NE(at, std::string::npos);
  const auto in_space_order = [](const dem::Simulation& sim) {
    const std::vector<std::int32_t> order = dem::spatial_order(sim.particles(), sim.cell());
    for (std::size_t k = 0; k < order.size(); ++k)
      if (order[k] != static_cast<std::int32_t>(k)) return false;
    return true;
  };
  const dem::Simulation small = io::build_simulation(io::parse_scene(yaml));
  EXPECT_EQ(small.particles().size(), 1000u);
  EXPECT_FALSE(in_space_order(small));  // the generator's order (decreasing radius)
  std::string big_yaml = yaml;
  big_yaml.replace(at, 11, "count: 2000");
  const dem::Simulation big = io::build_simulation(io::parse_scene(big_yaml));
  EXPECT_EQ(big.particles().size(), 2000u);
  EXPECT_TRUE(in_space_order(big));
}
