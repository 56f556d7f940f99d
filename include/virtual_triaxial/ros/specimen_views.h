// dem_node's views of the specimen (ROS adapter): VTK snapshots on disk and
// RViz markers on a latched topic. Both off unless asked for; when off,
// a control tick costs two tests.
//
// Parameters (private, `~`):
//   snapshot_dir        ""     directory of the VTK snapshot series
//                              (io/vtk_snapshot_writer.h); "" = none. Snapshots
//                              at every load, every pause after stepping (the
//                              protocol node pauses at each stage end, so
//                              every stage's end state is there), and every
//                              snapshot_interval steps between.
//   snapshot_interval   scene  steps between snapshots, counted from the load
//                              (written at the first control tick that
//                              reaches a multiple); default: the loaded
//                              scene's output.snapshot_interval (0 for a
//                              sample file); 0 = only load and pauses
//   markers             false  publish `specimen_markers`
//                              (visualization_msgs/MarkerArray, latched;
//                              ros/specimen_markers.h)
//   marker_period       1.0    wall seconds between marker updates while
//                              stepping (also sent at load and pause)
//   marker_forces       0      strongest contacts drawn as lines (0: none)
//   marker_max_particles 20000 decimation above this (every k-th particle)
//   marker_frame        "cell" frame_id of the markers
// Bad values throw std::invalid_argument naming the parameter.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <ros/ros.h>

#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/io/vtk_snapshot_writer.h"
#include "virtual_triaxial/ros/specimen_markers.h"

namespace vt::ros {

class SpecimenViews {
 public:
  SpecimenViews(::ros::NodeHandle& nh, const ::ros::NodeHandle& pnh);
  /// A specimen was loaded; scene_interval = its output.snapshot_interval.
  void on_load(const dem::Simulation& sim, std::int64_t scene_interval, const std::string& source);
  /// After every control tick.
  void on_tick(const dem::Simulation& sim) {
    if (series_ && interval_ > 0 && (sim.steps() - base_step_) / interval_ > last_block_) snapshot(sim, "step");
    if (markers_ && (::ros::WallTime::now() - last_markers_).toSec() >= marker_period_) publish_markers(sim);
  }
  /// The node was paused.
  void on_pause(const dem::Simulation& sim);

 private:
  void snapshot(const dem::Simulation& sim, const std::string& label);
  void publish_markers(const dem::Simulation& sim);

  std::unique_ptr<io::VtkSnapshotSeries> series_;
  std::int64_t interval_ = 0;
  bool interval_given_ = false;
  std::int64_t base_step_ = 0;   ///< step count at the load
  std::int64_t last_block_ = 0;  ///< (steps - base) / interval at the last interval snapshot
  bool markers_ = false;
  double marker_period_ = 1.0;
  MarkerOptions marker_options_;
  ::ros::Publisher marker_pub_;
  ::ros::WallTime last_markers_;
};

}  // namespace vt::ros
