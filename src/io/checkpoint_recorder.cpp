// Checkpoints of a headless run. See checkpoint_recorder.h.
#include "virtual_triaxial/io/checkpoint_recorder.h"

#include <chrono>
#include <cstdio>

#include "virtual_triaxial/io/checkpoint_file.h"

namespace vt::io {

void CheckpointRecorder::on_checkpoint(const protocol::RunCheckpoint& c, const dem::Simulation& sim) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string where = "stage " + std::to_string(c.stage_index) + " at stage step " + std::to_string(c.stage_steps);
  results_.flush_partial("the run stopped after its checkpoint (" + where + "); triax_run --resume " +
                         results_.path() + " continues it");
  CheckpointFile f;
  f.state = sim.state();
  f.run = c;
  f.scene_path = scene_path_;
  f.scene_text = scene_text_;
  f.results_rows = static_cast<std::int64_t>(results_.rows());
  write_checkpoint(path_, f);
  ++count_;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!quiet_)
    std::fprintf(stderr, "[checkpoint] %s (%s, %lld samples; written with the results in %.3f s)\n", path_.c_str(),
                 where.c_str(), static_cast<long long>(f.results_rows), seconds);
}

}  // namespace vt::io
