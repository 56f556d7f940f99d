// dem_node: the specimen and the cell of the virtual rig -- the "hardware"
// (DESIGN §6). A thin adapter between ROS and dem::Simulation.
//
// Parameters (private, `~`):
//   sample                  HDF5 sample file (io/sample_file.h; a .yaml } exactly
//                           path is taken as a scene / protocol)      }
//   scene                   YAML scene (config/scenes/README.md)       } one
//   publish_every     10    DEM steps per control tick (int >= 1)
//   lockstep          true  wait for every closed-loop owner's command each tick
//   lockstep_timeout  2.0   wall seconds to wait before holding the last command
//   max_dimensionless_rate 1e-3  limit on |eps'| = |rate| T0 of set_strain_rate
//                           and of cell commands
//   start_paused      false start paused (deterministic set-up, then resume/step)
//   diagnostics_period 1.0  wall seconds between /diagnostics reports
//   clock_rate        200   /clock messages per wall second at most while
//                           stepping (0: one per control tick); /clock also goes
//                           out on pause and load. Like a simulator's clock
//                           throttle: every state message carries its exact
//                           simulation time in its header, and each /clock
//                           message costs a send to every node on
//                           use_sim_time (rosout, recorder, clients).
//   damping_model, damping_ratio, time_step_ratio   override the file's values
//                           (applied again on every load_sample)
//   snapshot_dir, snapshot_interval, markers, marker_period, marker_forces,
//   marker_max_particles, marker_frame: views of the specimen (VTK snapshots,
//   RViz markers on `specimen_markers`), ros/specimen_views.h; off by default
// Bad parameters: the constructor throws, naming the parameter.
//
// Topics (relative to the node's namespace; one rig per namespace):
//   publishes  stress, strain, moment_index, kinetic_energy, fabric (each
//              control tick), /clock (simulation time, rosgraph_msgs/Clock;
//              at most clock_rate per wall second),
//              /diagnostics (every diagnostics_period and on timeouts/failure)
//   subscribes cell_command (virtual_triaxial/CellCommand)
// Services: set_strain_rate, claim_axes, release_axes, get_info, pause,
//   resume, step, load_sample, save_sample, set_damping, set_friction,
//   reset_strain (std_srvs/Trigger: strain reference := current cell).
//   load_sample with `resume`: a test's checkpoint goes on (state as saved,
//   strain reference kept, tick count continued: a resumed bag continues
//   the tick numbering). get_info's answered_tick says when every owner's
//   command for a tick is in (a rig checkpoint reads the next rates then).
//   Refusals name the request field; the node keeps running unchanged.
// Live tuning: dynamic_reconfigure ~set_parameters (damping_model,
//   damping_ratio), applied between control ticks (ros/dem_reconfigure.h).
//
// Control tick k: apply the current rates (open-loop rates, and for owned
// axes the owner's last command) for publish_every DEM steps, measuring on
// the last one; publish tick k (stamped with simulation time at its end);
// then, in lockstep mode, process callbacks until every owner that held its
// claim when tick k was published has sent a cell_command with tick k, or
// until lockstep_timeout wall seconds passed (the missing owners' last
// commands are held, counted, reported on /diagnostics; never a deadlock).
// Free-running mode never waits and uses the newest command. In lockstep the
// trajectory depends only on the commands (and on service calls made while
// paused), not on wall-clock timing.
//
// Strain rates r [1/s] on every interface are rates of the LOGARITHMIC strain,
// compression positive. The cell's velocity gradient for one step is set to
// l = expm1(-r dt) / dt (extension positive), so each DEM step changes the log
// strain by exactly r dt (the plain l = -r would lag by r dt / 2 relative).
//
// All ROS time handling is wall-clock (WallTime/WallDuration), so the node
// works with use_sim_time=true on the clock it publishes itself.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>

#include "virtual_triaxial/CellCommand.h"
#include "virtual_triaxial/ClaimAxes.h"
#include "virtual_triaxial/GetInfo.h"
#include "virtual_triaxial/LoadSample.h"
#include "virtual_triaxial/ReleaseAxes.h"
#include "virtual_triaxial/SaveSample.h"
#include "virtual_triaxial/SetDamping.h"
#include "virtual_triaxial/SetFriction.h"
#include "virtual_triaxial/SetStrainRate.h"
#include "virtual_triaxial/Step.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/io/sample_file.h"
#include "virtual_triaxial/ros/axis_arbiter.h"
#include "virtual_triaxial/ros/dem_diagnostics.h"
#include "virtual_triaxial/ros/dem_reconfigure.h"
#include "virtual_triaxial/ros/specimen_loader.h"
#include "virtual_triaxial/ros/specimen_views.h"

namespace vt::ros {

class DemNode {
 public:
  /// nh: the rig's namespace (topics, services); pnh: private parameters.
  DemNode(const ::ros::NodeHandle& nh, const ::ros::NodeHandle& pnh);
  /// Runs control ticks and serves callbacks until ROS shuts down or stop().
  void spin();
  /// Makes spin() return after the current tick (thread-safe; the nodelet's unload).
  void stop() { stop_ = true; }

 private:
  void read_parameters();
  void install(Specimen s);
  void advertise();

  void run_tick();
  void wait_for_commands();
  void publish_state(const dem::Vec3& rates);
  void publish_clock();
  void publish_diagnostics();
  bool stepping() const;

  void on_command(const virtual_triaxial::CellCommand::ConstPtr& msg);
  bool on_set_strain_rate(virtual_triaxial::SetStrainRate::Request& rq, virtual_triaxial::SetStrainRate::Response& rs);
  bool on_claim(virtual_triaxial::ClaimAxes::Request& rq, virtual_triaxial::ClaimAxes::Response& rs);
  bool on_release(virtual_triaxial::ReleaseAxes::Request& rq, virtual_triaxial::ReleaseAxes::Response& rs);
  bool on_get_info(virtual_triaxial::GetInfo::Request& rq, virtual_triaxial::GetInfo::Response& rs);
  bool on_pause(std_srvs::Trigger::Request& rq, std_srvs::Trigger::Response& rs);
  bool on_resume(std_srvs::Trigger::Request& rq, std_srvs::Trigger::Response& rs);
  bool on_reset_strain(std_srvs::Trigger::Request& rq, std_srvs::Trigger::Response& rs);
  bool on_step(virtual_triaxial::Step::Request& rq, virtual_triaxial::Step::Response& rs);
  bool on_load(virtual_triaxial::LoadSample::Request& rq, virtual_triaxial::LoadSample::Response& rs);
  bool on_save(virtual_triaxial::SaveSample::Request& rq, virtual_triaxial::SaveSample::Response& rs);
  bool on_set_damping(virtual_triaxial::SetDamping::Request& rq, virtual_triaxial::SetDamping::Response& rs);
  bool on_set_friction(virtual_triaxial::SetFriction::Request& rq, virtual_triaxial::SetFriction::Response& rs);

  ::ros::NodeHandle nh_, pnh_;
  ::ros::CallbackQueue queue_;  ///< every callback of this node; spun by spin()

  // parameters
  int publish_every_ = 10;
  int threads_ = 0;  ///< ~threads; 0 = ThreadGovernor
  bool lockstep_ = true;
  double lockstep_timeout_ = 2.0;
  double max_dimensionless_rate_ = 1e-3;
  double diagnostics_period_ = 1.0;
  double clock_period_ = 0.005;     ///< wall seconds between /clock messages while stepping (0: every tick)
  ::ros::WallTime last_clock_;
  std::unique_ptr<SpecimenLoader> loader_;

  // state
  std::unique_ptr<dem::Simulation> sim_;
  io::SampleMetadata meta_;
  std::string source_;
  AxisArbiter arbiter_;
  DemDiagnostics diag_;
  std::uint64_t tick_ = 0;           ///< last published control tick
  std::uint64_t answered_tick_ = 0;  ///< last tick whose lockstep wait has ended
  std::uint64_t pending_ticks_ = 0;  ///< ticks requested by `step` while paused
  bool paused_ = false;
  std::atomic<bool> stop_{false};
  ::ros::WallTime last_diagnostics_;

  ::ros::Publisher stress_pub_, strain_pub_, moment_pub_, energy_pub_, fabric_pub_, clock_pub_, diag_pub_;
  ::ros::Subscriber command_sub_;
  std::vector<::ros::ServiceServer> services_;
  std::unique_ptr<DemReconfigure> reconfigure_;  ///< live tuning; on pnh_ (queue_)
  std::unique_ptr<SpecimenViews> views_;         ///< snapshots and RViz markers (off by default)
};

}  // namespace vt::ros
