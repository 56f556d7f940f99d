// Writes VTK snapshots of the specimen (vtk_snapshot_writer.h) during a
// StageRunner run: at the start and at the end of every stage ("before and
// after" each stage, e.g. before and after shearing) and, when
// `interval` > 0 (scene key output.snapshot_interval), on every sample
// whose step count since the stage start is a multiple of `interval`. A
// step is never written twice. Reads the Simulation only (SpecimenSnapshot).
#pragma once

#include <cstdint>
#include <string>

#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/io/vtk_snapshot_writer.h"
#include "virtual_triaxial/protocol/stage_runner.h"

namespace vt::io {

class SnapshotRecorder : public protocol::RunObserver {
 public:
  SnapshotRecorder(const dem::Simulation& sim, VtkSnapshotSeries& series, std::int64_t interval)
      : sim_(sim), series_(series), interval_(interval) {}
  void on_stage_start(const protocol::StageSpec& st, const dem::Simulation& sim) override;
  void on_sample(const protocol::StageSpec& st, const dem::Measures& m) override;
  void on_stage_end(const protocol::StageOutcome& out) override;

 private:
  void write(const std::string& label);

  const dem::Simulation& sim_;
  VtkSnapshotSeries& series_;
  std::int64_t interval_ = 0;
  std::int64_t stage_start_step_ = 0;
};

}  // namespace vt::io
