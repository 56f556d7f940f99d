// Three-phase sample preparation (chapter 4.3) on small samples: final
// stresses within tolerance, equilibrium (eq. 54), aspect ratios, overlaps,
// reproducibility, e rising with mu1 and falling with pressure, and the
// target-void-ratio search.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "virtual_triaxial/dem/cloud_generator.h"
#include "virtual_triaxial/io/sample_file.h"
#include "virtual_triaxial/protocol/sample_preparation.h"
#include "virtual_triaxial/protocol/void_ratio_search.h"

using namespace vt;
using protocol::PreparationResult;
using protocol::PreparationSettings;

namespace {

PreparationSettings small(double mu1, double pressure = 100e3, std::int64_t n = 160) {
  PreparationSettings s;
  s.radii = dem::table_radii(n, {{0.8e-3, 0.25}, {0.933e-3, 0.25}, {1.067e-3, 0.25}, {1.2e-3, 0.25}});
  s.mu1 = mu1;
  s.pressure = pressure;
  s.seed = 4;
  return s;
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

}  // namespace

TEST(SamplePreparation, MeetsStressEquilibriumAspectAndOverlapCriteria) {
  PreparationSettings s = small(0.2);
  s.aspect = {1.0, 1.0, 4.0 / 3.0};  // table 2: 1, 1, 4/3
  const PreparationResult r = protocol::prepare_sample(s);
  ASSERT_TRUE(r.converged) << r.failure;
  const dem::Measures& m = r.final;
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(m.stress(a, a) / s.pressure, 1.0, s.tolerance) << "axis " << a;
  EXPECT_LT(m.iuf * m.iuf, s.ufr_threshold) << "eq. 54";
  EXPECT_NEAR(r.aspect.y / r.aspect.x, 1.0, 0.01);
  EXPECT_NEAR(r.aspect.z / r.aspect.x, 4.0 / 3.0, 0.01 * 4.0 / 3.0);
  EXPECT_LT(m.max_overlap_ratio, 0.01) << "no overlap above 1 % of the smaller radius";
  EXPECT_GT(m.coordination_number, 3.5) << "a load-bearing network";
  ASSERT_EQ(r.phases.size(), 3u);
  EXPECT_EQ(r.phases[0].name, "generation");
  EXPECT_GT(r.phases[1].cycles, 0);
  EXPECT_GT(r.phases[2].steps, 0);
  // The sample carries the final friction, not mu1.
  EXPECT_EQ(r.state.settings.material.friction, 0.5);
}

TEST(SamplePreparation, SameInputsAndSeedGiveAByteIdenticalFile) {
  const auto dir = std::filesystem::temp_directory_path() / ("vt_prep_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::string bytes[2];
  for (int k = 0; k < 2; ++k) {
    const PreparationResult r = protocol::prepare_sample(small(0.3));
    ASSERT_TRUE(r.converged) << r.failure;
    io::SampleMetadata meta;
    meta.seed = 4;
    meta.friction_during_shrinkage = 0.3;
    io::write_sample((dir / "s.h5").string(), r.state, meta);
    bytes[k] = slurp(dir / "s.h5");
  }
  std::filesystem::remove_all(dir);
  ASSERT_GT(bytes[0].size(), 1000u);
  EXPECT_TRUE(bytes[0] == bytes[1]);
  // A different seed gives a different sample.
  PreparationSettings other = small(0.3);
  other.seed = 5;
  const PreparationResult a = protocol::prepare_sample(small(0.3)), b = protocol::prepare_sample(other);
  EXPECT_NE(a.final.void_ratio, b.final.void_ratio);
}

TEST(SamplePreparation, VoidRatioRisesWithMu1AndFallsWithPressure) {
  double previous = 0;
  for (double mu1 : {0.0, 0.1, 0.3, 0.5}) {
    const PreparationResult r = protocol::prepare_sample(small(mu1));
    ASSERT_TRUE(r.converged) << "mu1 " << mu1 << ": " << r.failure;
    std::printf("mu1 %.2f: e %.4f Z %.3f\n", mu1, r.final.void_ratio, r.final.coordination_number);
    EXPECT_GT(r.final.void_ratio, previous) << "fig. 11: e must rise with mu1 (mu1 = " << mu1 << ")";
    previous = r.final.void_ratio;
  }
  const PreparationResult low = protocol::prepare_sample(small(0.3, 100e3));
  const PreparationResult high = protocol::prepare_sample(small(0.3, 39e6));  // table 49 top pressure
  ASSERT_TRUE(low.converged && high.converged);
  EXPECT_LT(high.final.void_ratio, low.final.void_ratio) << "fig. 12: e falls as the pressure rises";
}

TEST(SamplePreparation, TargetVoidRatioIsHitOrReportedOutOfReach) {
  const PreparationResult dense = protocol::prepare_sample(small(0.0));
  const PreparationResult loose = protocol::prepare_sample(small(0.5));
  ASSERT_TRUE(dense.converged && loose.converged);
  const double target = 0.5 * (dense.final.void_ratio + loose.final.void_ratio);
  const protocol::VoidRatioSearch hit = protocol::find_mu1_for_void_ratio(small(0.0), target, 0.005);
  ASSERT_TRUE(hit.reachable) << hit.message;
  EXPECT_NEAR(hit.result.final.void_ratio, target, 0.005);
  EXPECT_GT(hit.mu1, 0.0);
  EXPECT_LT(hit.mu1, 0.5);
  const protocol::VoidRatioSearch miss = protocol::find_mu1_for_void_ratio(small(0.0), 3.0, 0.005);
  EXPECT_FALSE(miss.reachable);
  EXPECT_NE(miss.message.find("out of reach"), std::string::npos) << miss.message;
}

TEST(SamplePreparation, BadSettingsNameTheField) {
  struct Case {
    PreparationSettings s;
    const char* field;
  };
  std::vector<Case> cases;
  PreparationSettings s = small(0.3);
  s.radii.clear();
  cases.push_back({s, "psd"});
  s = small(0.3), s.pressure = 0;
  cases.push_back({s, "pressure"});
  s = small(0.3), s.pressure = -5;
  cases.push_back({s, "pressure"});
  s = small(0.3), s.mu1 = -0.1;
  cases.push_back({s, "mu1"});
  s = small(0.3), s.aspect = {1, 0, 1};
  cases.push_back({s, "aspect"});
  for (const Case& c : cases) {
    try {
      protocol::prepare_sample(c.s);
      ADD_FAILURE() << "accepted bad " << c.field;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind(c.field, 0), 0u) << e.what();
    }
  }
}
