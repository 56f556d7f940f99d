// Energy budget over the default scene (config/scenes/default.yaml):
// boundary work = change in kinetic and elastic energy + damping + friction
// dissipation, within 1 % of the boundary work, at every recorded sample.
#include <gtest/gtest.h>

#include <cmath>

#include "virtual_triaxial/io/scene_builder.h"
#include "virtual_triaxial/io/scene_parser.h"
#include "virtual_triaxial/protocol/stage_runner.h"

using namespace vt;

namespace {

class BudgetWatcher : public protocol::RunObserver {
 public:
  void on_sample(const protocol::StageSpec&, const dem::Measures& m) override {
    const dem::EnergyBudget& e = m.energy;
    if (e.boundary_work > 0) worst = std::max(worst, std::fabs(e.balance_error()) / e.boundary_work);
    last = e;
    ++samples;
  }
  double worst = 0;
  dem::EnergyBudget last;
  int samples = 0;
};

}  // namespace

TEST(EnergyBudget, DefaultSceneBalancesWithinOnePercent) {
  const io::SceneConfig scene = io::load_scene(std::string(VT_SOURCE_DIR) + "/config/scenes/default.yaml");
  dem::Simulation sim = io::build_simulation(scene);
  protocol::RunOptions opt;
  opt.sample_interval = scene.output.interval;
  opt.progress_seconds = 0;
  opt.keep_last_good = false;
  protocol::StageRunner runner(sim, opt);
  BudgetWatcher w;
  const protocol::RunReport r = runner.run(scene.stages, w);
  ASSERT_EQ(r.verdict, protocol::Verdict::Completed) << r.failure;
  ASSERT_GT(w.samples, 100);
  const dem::EnergyBudget& e = w.last;
  EXPECT_GT(e.boundary_work, 0.0);
  EXPECT_GT(e.damping, 0.0);
  EXPECT_GT(e.friction, 0.0) << "shearing a frictional packing must dissipate by sliding";
  EXPECT_GT(e.elastic, 0.0);
  EXPECT_LT(w.worst, 0.01) << "W = " << e.boundary_work << " J, dKE + dU + D + Fr = "
                           << e.kinetic() - e.kinetic_reference + e.elastic - e.elastic_reference + e.damping + e.friction;
  std::printf("energy budget: W %.4g J = KE %.3g + U %.3g + damping %.4g + friction %.4g; worst error %.2e of W\n",
              e.boundary_work, e.kinetic(), e.elastic, e.damping, e.friction, w.worst);
}
