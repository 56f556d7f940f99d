#include "virtual_triaxial/io/snapshot_recorder.h"

namespace vt::io {

void SnapshotRecorder::write(const std::string& label) {
  if (series_.last_step() == sim_.steps()) return;
  series_.write(dem::SpecimenSnapshot::of(sim_), label);
}

void SnapshotRecorder::on_stage_start(const protocol::StageSpec& st, const dem::Simulation&) {
  stage_start_step_ = sim_.steps();
  write("stage " + st.name + " start");
}

void SnapshotRecorder::on_sample(const protocol::StageSpec& st, const dem::Measures&) {
  const std::int64_t k = sim_.steps() - stage_start_step_;
  if (interval_ > 0 && k > 0 && k % interval_ == 0) write("stage " + st.name + " step " + std::to_string(k));
}

void SnapshotRecorder::on_stage_end(const protocol::StageOutcome& out) { write("stage " + out.name + " end"); }

}  // namespace vt::io
