// The stability map's boundary, pinned (reports/stability_map/, issue 16): a
// few points of the map on each side of a boundary, re-run here as the map
// runs them (the 200-sphere sample of tests/data, consolidated at 100 kPa,
// drained shear at eps' = 1e-6 for 20 000 steps, PID-free proportional servo
// of drained_mini.yaml), so a change that moves a boundary is noticed:
//   - OD xi 0.3 % (the dissertation's setting) at c_t 0.3: completes, energy
//     balance error within 1 %, lateral stresses within 20 % of 100 kPa;
//   - undamped and OD 0.3 % stay stable up to c_t 3.5 (the Hertz contacts of
//     this packing allow about 4.6 T0) and blow up at c_t 7 (the stability
//     monitor's verdict `unstable`, within the first steps of the shear);
//   - viscous damping at e = 0.1 (strong dashpots, integrated explicitly):
//     the energy balance error passes 1 % between c_t 0.1 (within) and c_t
//     0.5 (beyond), long before the blow-up.
// One OpenMP thread.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <omp.h>

#include "virtual_triaxial/io/scene_builder.h"
#include "virtual_triaxial/io/scene_parser.h"
#include "virtual_triaxial/protocol/stage_runner.h"

using namespace vt;

namespace {

struct Point {
  protocol::RunReport report;
  double energy_error = 0;
  double lateral_error = 0;  ///< largest |sigma_lateral - 100 kPa| / 100 kPa over the shear's samples
};

struct LateralWatch : protocol::RunObserver {
  double worst = 0;
  void on_sample(const protocol::StageSpec& st, const dem::Measures& m) override {
    if (!protocol::is_shear(st.type)) return;
    for (int a = 0; a < 2; ++a) worst = std::max(worst, std::abs(m.stress.m[a][a] - 1e5) / 1e5);
  }
};

/// `damping`: "OD", "viscous", ...; `value`: its one parameter.
Point run(const std::string& model, double value, double c_t) {
  omp_set_num_threads(1);
  io::SceneConfig scene = io::load_scene(VT_SOURCE_DIR "/tests/data/protocols/drained_mini.yaml");
  const std::string key = model == "viscous" ? "restitution" : (model == "local" ? "coefficient" : "ratio");
  const io::SceneConfig damped = io::parse_scene(
      "particles:\n  distribution: {count: 10, radius_min: 1.0e-3, radius_max: 1.0e-3}\n"
      "stages:\n  - {type: relax, stop: {steps: 1}}\n"
      "damping: {model: " + model + ", " + key + ": " + std::to_string(value) + "}\n");
  scene.damping = damped.damping;
  scene.time_step_ratio = c_t;
  scene.stages[1].strain_rate_dimensionless = 1e-6;
  scene.stages[1].stop = {};
  scene.stages[1].stop.steps = 20000;
  dem::Simulation sim = io::build_simulation(scene);
  protocol::RunOptions opt = scene.run_options();
  opt.progress_seconds = 0;
  protocol::StageRunner runner(sim, opt);
  LateralWatch watch;
  Point p;
  p.report = runner.run(scene.stages, watch);
  p.energy_error = sim.energy().relative_balance_error();
  p.lateral_error = watch.worst;
  return p;
}

std::int64_t shear_steps(const Point& p) { return p.report.stages.size() > 1 ? p.report.stages[1].steps : 0; }

}  // namespace

TEST(StabilityBoundary, TheDissertationsSettingIsStableAndBalanced) {
  const Point p = run("OD", 0.003, 0.3);
  ASSERT_EQ(p.report.verdict, protocol::Verdict::Completed) << p.report.failure;  // stopped by its 20 000 steps
  EXPECT_EQ(shear_steps(p), 20000);
  EXPECT_LT(std::abs(p.energy_error), 0.01);
  EXPECT_LT(p.lateral_error, 0.2);
}

TEST(StabilityBoundary, MassDampedRunsBlowUpBetweenCt3p5And7) {
  for (const double xi : {0.0, 0.003}) {
    const Point below = run("OD", xi, 3.5);
    EXPECT_EQ(below.report.verdict, protocol::Verdict::Completed) << "xi " << xi << ": " << below.report.failure;
    EXPECT_EQ(shear_steps(below), 20000) << "xi " << xi;
    const Point above = run("OD", xi, 7.0);
    EXPECT_EQ(above.report.verdict, protocol::Verdict::Unstable) << "xi " << xi << ": c_t 7 did not blow up";
  }
}

TEST(StabilityBoundary, StrongViscousDampingLosesTheEnergyBalanceBetweenCt0p1And0p5) {
  const Point within = run("viscous", 0.1, 0.1);
  EXPECT_NE(within.report.verdict, protocol::Verdict::Unstable) << within.report.failure;
  EXPECT_LT(std::abs(within.energy_error), 0.01);
  const Point beyond = run("viscous", 0.1, 0.5);
  EXPECT_NE(beyond.report.verdict, protocol::Verdict::Unstable) << beyond.report.failure;
  EXPECT_GT(std::abs(beyond.energy_error), 0.01);
}
