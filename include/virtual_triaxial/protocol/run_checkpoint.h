// A run's checkpoint inside a stage (ROS-free): with the simulation state
// (dem::SimulationState) it is everything that affects the later steps, so
// StageRunner::run(..., &checkpoint) continues a killed run and finishes it
// exactly as the uninterrupted run (same samples, same summary, bit for bit).
// Taken on a sample tick, after the sample is recorded, so the state is also
// the run's last good state there. io/checkpoint_file.h stores it.
#pragma once

#include <cstdint>
#include <vector>

#include "virtual_triaxial/protocol/stage_judge.h"
#include "virtual_triaxial/protocol/stage_judge_state.h"
#include "virtual_triaxial/protocol/stage_runner.h"

namespace vt::protocol {

struct RunCheckpoint {
  std::size_t stage_index = 0;        ///< the stage running
  std::int64_t stage_steps = 0;       ///< DEM steps of that stage so far
  double rates[3] = {0, 0, 0};        ///< log-strain rates of the next tick [1/s], compression positive
  std::vector<StageOutcome> finished; ///< the stages before it
  std::int64_t steps = 0;             ///< RunReport::steps (finished stages)
  std::int64_t ticks = 0;             ///< RunReport::ticks (all ticks so far)
  double wall_seconds = 0;            ///< wall time of the run so far [s] (informative)
  StageJudgeState judge;
  SpecimenAtStart specimen;           ///< the stage's specimen at its start (the rate strategies' eq. 84)
  bool servo = false;                 ///< the stage runs a servo
  std::vector<double> servo_memory;   ///< control::ServoStrategy::memory()
  double servo_start_time = 0;        ///< simulation time the servo started at [s]
  // The ROS rig only (headless: 0 / empty): its controllers are nodes with
  // memories of their own, and dem_node counts the ticks the bag records.
  std::uint64_t rig_tick = 0;                   ///< dem_node's control tick of the checkpoint
  std::vector<double> rate_controller_memory;  ///< the rate controller node's ~get_memory
  std::int64_t lockstep_timeouts = 0;          ///< dem_node's lockstep timeouts of the run so far
};

/// The part of a checkpoint both runners fill alike, on a sample tick of
/// stage `stage_index` after `stage_steps` of its steps: the next tick's
/// log-strain rates [1/s], the finished stages and counts of `report`, the
/// judge's memory and the stage's specimen at its start; `servo` says
/// whether the stage runs one (its memory is the runner's to add: an object
/// headless, a node on the rig).
inline RunCheckpoint checkpoint_of(std::size_t stage_index, std::int64_t stage_steps, const double (&rates)[3],
                                   const RunReport& report, double wall_seconds, const StageJudge& judge,
                                   const SpecimenAtStart& specimen, bool servo) {
  RunCheckpoint c;
  c.stage_index = stage_index;
  c.stage_steps = stage_steps;
  for (int a = 0; a < 3; ++a) c.rates[a] = rates[a];
  c.finished = report.stages;
  c.steps = report.steps;
  c.ticks = report.ticks;
  c.wall_seconds = wall_seconds;
  c.judge = judge.save_state();
  c.specimen = specimen;
  c.servo = servo;
  return c;
}

}  // namespace vt::protocol
