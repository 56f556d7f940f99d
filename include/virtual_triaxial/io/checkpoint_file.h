// Checkpoint file of a run inside a stage (protocol/run_checkpoint.h): one
// HDF5 file, written atomically (hdf5_atomic_file.h), that is a sample file
// (sample_file.h layout at the root: the state to continue from, so any
// tool that loads samples loads it) plus
//   /checkpoint  attrs format "virtual_triaxial checkpoint", format_version,
//                scene_path (absolute), scene_text (the file as it was run),
//                results_rows (samples in the results file at the checkpoint),
//                stage_index, stage_steps, steps, ticks (int64),
//                wall_seconds [s], servo (int64 0/1), servo_start_time [s],
//                specimen_void_ratio, specimen_dispersity_index [1] (at the stage start),
//                rig_tick, lockstep_timeouts (int64; the ROS rig's, absent
//                in a headless checkpoint: 0),
//                finished (int64 count) and per finished stage i:
//                finished_<i>_name, _type (int64), _steps, _stop_reason
//     /rates          (3) float64 [1/s] next tick's log-strain rates
//     /servo_memory   (n) float64 [1]  control::ServoStrategy::memory() (absent: none)
//     /rate_strategy  (n) float64 [1]  the judge's rate strategy memory (absent: none)
//     /rate_controller_memory (n) float64 [1]  the rig's rate controller node's (absent: none)
//   /checkpoint/judge  attrs: the judge's numbers (stage_judge_state.h to_fields)
// Doubles round-trip bit for bit. Errors name the file and the field.
#pragma once

#include <cstdint>
#include <string>

#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/protocol/run_checkpoint.h"

namespace vt::io {

inline constexpr const char* kCheckpointFormat = "virtual_triaxial checkpoint";
inline constexpr std::int64_t kCheckpointFormatVersion = 1;

struct CheckpointFile {
  dem::SimulationState state;
  protocol::RunCheckpoint run;
  std::string scene_path;   ///< absolute path of the scene / protocol file
  std::string scene_text;   ///< its contents when the run started
  std::int64_t results_rows = 0;
};

/// Atomic; throws WriteError (hdf5_atomic_file.h) when the disk refuses.
void write_checkpoint(const std::string& path, const CheckpointFile& c);
/// Throws std::runtime_error "<file>: <field>: <reason>".
CheckpointFile read_checkpoint(const std::string& path);

}  // namespace vt::io
