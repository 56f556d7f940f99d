// The adaptive rate strategy on a real shear through the peak (issue 16):
// the 200-sphere sample of tests/data (e0 0.71, 100 kPa) sheared by the
// StageRunner with rate.strategy adaptive (tests/data/protocols/adaptive_mini.yaml,
// I_QS 0.05 and target 0.5 so that it runs in seconds; here at c_t 0.3) to 6 % axial
// strain. Asserted:
//   - the run passes its peak (phi_peak before 5.5 % and phi at the end
//     below it): the band is tested through the peak, where the packing
//     rearranges and the index rises at a fixed rate;
//   - after the start-up (the first 0.5 % of strain, the law's response
//     time), the running mean of I_mom over 5 samples (1000 steps) stays within
//     [0.6, 1.5] x target I_QS on every sample; and the mean to the peak within
//     10 % of target I_QS;
//   - the law used its range: eps' varied by more than 2x.
// One OpenMP thread.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <deque>
#include <numeric>

#include <omp.h>

#include "virtual_triaxial/io/scene_builder.h"
#include "virtual_triaxial/io/scene_parser.h"
#include "virtual_triaxial/protocol/stage_runner.h"

using namespace vt;

namespace {

struct Samples : protocol::RunObserver {
  std::vector<dem::Measures> shear;
  void on_sample(const protocol::StageSpec& st, const dem::Measures& m) override {
    if (protocol::is_shear(st.type)) shear.push_back(m);
  }
};

struct ShearRun {
  protocol::RunReport report;
  std::vector<dem::Measures> shear;
};

ShearRun run() {
  omp_set_num_threads(1);
  io::SceneConfig scene = io::load_scene(VT_SOURCE_DIR "/tests/data/protocols/adaptive_mini.yaml");
  scene.time_step_basis = dem::TimeStepBasis::ReferenceTime;  // the file's contacts basis is for the rig test
  scene.time_step_ratio = 0.3;
  scene.stages[1].stop.axial_strain = 0.06;
  dem::Simulation sim = io::build_simulation(scene);
  protocol::RunOptions opt = scene.run_options();
  opt.progress_seconds = 0;
  protocol::StageRunner runner(sim, opt);
  Samples rec;
  ShearRun r;
  r.report = runner.run(scene.stages, rec);
  r.shear = rec.shear;
  return r;
}

}  // namespace

TEST(AdaptiveRateRun, TheMomentIndexStaysInItsBandThroughThePeak) {
  const ShearRun r = run();
  ASSERT_EQ(r.report.verdict, protocol::Verdict::Completed) << r.report.failure;
  const protocol::ShearSummary& s = r.report.shear;
  ASSERT_TRUE(s.has_data);
  EXPECT_EQ(s.rate_strategy, "adaptive");
  const double target = 0.5 * 0.05;
  const double eps_end = r.shear.back().strain[2];
  std::printf("[adaptive] phi_peak %.2f deg at %.2f %%, phi_end %.2f deg at %.2f %%, mean I_mom to the peak %.4g "
              "(target %.4g), eps' %.3g .. %.3g, %zu samples\n",
              s.phi_peak * 180 / M_PI, 100 * s.eps_peak, s.phi_end * 180 / M_PI, 100 * eps_end,
              s.mean_moment_index_to_peak, target, s.strain_rate_min, s.strain_rate_max, r.shear.size());
  EXPECT_LT(s.eps_peak, 0.055) << "no peak before the end: the band is not tested through a peak";
  EXPECT_LT(s.phi_end, s.phi_peak - 0.01) << "no softening after the peak";
  EXPECT_NEAR(s.mean_moment_index_to_peak, target, 0.1 * target);
  EXPECT_GT(s.strain_rate_max, 2.0 * s.strain_rate_min) << "the law never moved the rate";
  std::deque<double> window;
  double lo = 1e9, hi = 0;
  for (const dem::Measures& m : r.shear) {
    window.push_back(m.moment_index);
    if (window.size() > 5) window.pop_front();
    if (m.strain[2] < 0.005 || window.size() < 5) continue;
    const double mean = std::accumulate(window.begin(), window.end(), 0.0) / 5.0;
    lo = std::min(lo, mean);
    hi = std::max(hi, mean);
    EXPECT_GE(mean, 0.6 * target) << "at eps_a " << m.strain[2];
    EXPECT_LE(mean, 1.5 * target) << "at eps_a " << m.strain[2];
  }
  std::printf("[adaptive] running mean of I_mom after 0.5 %%: %.3g .. %.3g x target\n", lo / target, hi / target);
}
