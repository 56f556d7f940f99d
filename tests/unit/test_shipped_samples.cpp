// The ready samples in config/samples/ load, continue exactly where they were
// saved, and meet the preparation criteria they claim: stresses within 0.5 %
// of 100 kPa on every axis, eq. 54 unbalanced force ratio below 1e-3, cubic
// cell within 1 %, and provenance metadata.
#include <gtest/gtest.h>

#include <filesystem>

#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/io/sample_file.h"

namespace fs = std::filesystem;
using namespace vt;

TEST(ShippedSamples, LoadAndMeetThePreparationCriteria) {
  int n = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(VT_SOURCE_DIR) / "config/samples")) {
    if (entry.path().extension() != ".h5") continue;
    ++n;
    const std::string name = entry.path().filename().string();
    io::SampleMetadata meta;
    dem::Simulation sim(io::read_sample(entry.path().string(), &meta));
    ASSERT_TRUE(sim.step(true)) << name << ": " << sim.failure();
    const dem::Measures m = sim.measures();
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(m.stress(a, a) / 100e3, 1.0, 0.005) << name << " axis " << a;
    EXPECT_LT(m.iuf * m.iuf, 1e-3) << name;
    const dem::Mat3& h = sim.cell().h();
    EXPECT_NEAR(h(1, 1) / h(0, 0), 1.0, 0.01) << name;
    EXPECT_NEAR(h(2, 2) / h(0, 0), 1.0, 0.01) << name;
    EXPECT_EQ(meta.target_pressure, 100e3) << name;
    EXPECT_NE(meta.created_by.find("triax_prepare"), std::string::npos) << name;
    EXPECT_EQ(sim.settings().material.friction, 0.5) << name;
    // dense samples are denser than loose ones of the same size
    if (name.rfind("dense", 0) == 0) {
      EXPECT_LT(m.void_ratio, 0.65) << name;
    }
    if (name.rfind("loose", 0) == 0) {
      EXPECT_GT(m.void_ratio, 0.70) << name;
    }
  }
  EXPECT_EQ(n, 5) << "config/samples holds five samples (four of spheres, one of spheroids)";
}
