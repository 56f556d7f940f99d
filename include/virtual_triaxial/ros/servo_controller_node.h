// servo_controller_node: the cell-pressure controller of the virtual rig
// (DESIGN §6). A thin adapter between ROS and control::ServoStrategy.
//
// Parameters (private, `~`):
//   target            (required) stress target of every controlled axis [Pa], >= 0
//   strategy          "proportional"  control::make_servo name: "proportional"
//                             (proportional_servo.h) or "pid" (pid_servo.h)
//   gain              0.5     dimensionless servo gain g (see proportional_servo.h)
//   ki                0       dimensionless integral gain, [0, 1]   } "pid" only
//   kd                0       dimensionless derivative gain, [0, 0.2] } (pid_servo.h)
//   max_rate_change   0       rate limit, DIMENSIONLESS like max_dimensionless_rate:
//                             cap on |rate_n - rate_{n-1}| T0 per control update
//                             (0 = off; "pid" only); the strategy gets it / T0
//   max_dimensionless_rate 1e-4  cap on |eps'| = |rate| T0 of the commands
//                             (T0 from dem_node's get_info); must not exceed
//                             dem_node's own ~max_dimensionless_rate
//   axes              [0, 1]  cell axes to control (the lateral ones by default)
//   owner             the node's name; the name used with claim_axes
//   start_enabled     true    claim the axes at start (retried every 0.2 s
//                             wall until dem_node is up)
// Bad parameters: the constructor throws, naming the parameter.
//
// Wiring (relative to the node's namespace, i.e. the rig's): subscribes
// `stress`, publishes `cell_command` and `servo_state`, calls dem_node's
// `get_info`, `claim_axes`, `release_axes`. Before claiming it waits until
// both topic connections to dem_node exist, so in lockstep mode no state of
// a claimed tick is missed. A call whose answer is lost is made again
// (idempotent_call.h); if dem_node ran a claim whose answer never came, the
// state it then waits on may arrive before a later claim succeeds: the
// newest state received while enabled and unclaimed is answered once a claim
// succeeds, if its tick is after the claim's (claim_axes answers the first
// claim's tick).
//
// Per Stress message of tick k: targets from the ramp at the message's
// simulation time, ServoStrategy::update(time, dt, stress, stiffness), then a
// CellCommand with tick k for the controlled axes and a ServoState.
// The servo dt is Stress.control_period = DEM dt * publish_every, NOT the DEM
// dt: dem_node applies the commanded rate for publish_every steps, so the
// strain increment rate * control_period is the one the law intends
// (g times the increment that cancels the error for the current stiffness).
// With a proportional law the error lags a steady drift d per control tick by
// about d/g, so shear tests want a small publish_every (see the rostest).
//
// Services, in the node's PRIVATE namespace (e.g. /servo/enable) so several
// controllers can share a rig: set_confining_pressure (target for every
// controlled axis, ramp in simulation seconds), set_axis_targets (per-axis
// targets, ramp), set_axes (change the controlled axes: release, then claim
// the new set when enabled), enable (claim + start; while the claim is
// pending its answer says "not claimed yet (why), retrying", which
// test_protocol_node reads to ask again before a stage), disable (stop +
// release_axes), get_memory / set_memory (GetMemory.srv / SetMemory.srv: the
// strategy's memory, e.g. the PID's integral, for a rig checkpoint and its
// resume; set_memory only while enabled and claimed).
// Refusals name the field.
//
// Live tuning (dynamic_reconfigure, cfg/Servo.cfg), in the private namespace:
// service ~set_parameters, topics ~parameter_updates / ~parameter_descriptions.
// gain, ki, kd, max_dimensionless_rate, max_rate_change (same meaning as the
// parameters above; the server starts from the node's parameter values). A
// change is applied between two control updates (the node is single-threaded:
// ros::spin) from the next Stress message on, without resetting the
// strategy's state (the PID integral term is in Pa, so a ki change does not
// jump). An invalid value (out of range, NaN, max_dimensionless_rate above
// dem_node's) is refused with a ROS_WARN naming the field and the old value is
// kept; the reply and ~parameter_updates (recorded by rosbag) carry the values
// in force; every accepted change is logged with ROS_INFO. dynamic_reconfigure
// mirrors the values in force to the private parameters (~gain, ...), so a
// restarted node on the same master starts with the tuned values.
// No ROS time is used (only WallTimer and message stamps), so use_sim_time
// is harmless.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <boost/thread/recursive_mutex.hpp>
#include <mutex>
#include <dynamic_reconfigure/server.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>

#include "virtual_triaxial/GetMemory.h"
#include "virtual_triaxial/ServoConfig.h"
#include "virtual_triaxial/SetMemory.h"
#include "virtual_triaxial/SetAxisTargets.h"
#include "virtual_triaxial/SetConfiningPressure.h"
#include "virtual_triaxial/SetServoAxes.h"
#include "virtual_triaxial/Stress.h"
#include "virtual_triaxial/control/servo_strategy.h"
#include "virtual_triaxial/ros/inline_callback_queue.h"
#include "virtual_triaxial/ros/target_ramp.h"

namespace vt::ros {

class ServoControllerNode {
 public:
  /// inline_stress: run the stress callback in the thread that delivers the
  /// message (InlineCallbackQueue; the nodelet rig: dem_node's thread), under
  /// the node's mutex, instead of in the node's own thread.
  ServoControllerNode(const ::ros::NodeHandle& nh, const ::ros::NodeHandle& pnh, bool inline_stress = false);

 private:
  void read_parameters();
  /// The strategy's parameters for dem_node's time scale T0 [s] (the
  /// dimensionless settings below, rates divided by T0).
  control::ServoParameters tuning(double t0) const;
  /// The settings as a dynamic_reconfigure config.
  virtual_triaxial::ServoConfig current_config() const;
  void on_reconfigure(virtual_triaxial::ServoConfig& config, std::uint32_t level);
  /// get_info + claim_axes; "" on success, else why not (yet).
  std::string try_claim();
  /// release_axes; "" on success. Without a claim recorded it still asks
  /// dem_node to release the axes (in case it lists a claim whose answer was
  /// lost) and ignores a refusal.
  std::string release();
  void on_retry(const ::ros::WallTimerEvent&);
  void on_stress(const virtual_triaxial::Stress::ConstPtr& msg);
  /// The law's command (and servo_state) for the state of tick `state.tick`.
  void answer(const virtual_triaxial::Stress& state);
  bool on_set_confining_pressure(virtual_triaxial::SetConfiningPressure::Request& rq,
                                 virtual_triaxial::SetConfiningPressure::Response& rs);
  bool on_set_axis_targets(virtual_triaxial::SetAxisTargets::Request& rq,
                           virtual_triaxial::SetAxisTargets::Response& rs);
  bool on_set_axes(virtual_triaxial::SetServoAxes::Request& rq, virtual_triaxial::SetServoAxes::Response& rs);
  bool on_enable(std_srvs::Trigger::Request& rq, std_srvs::Trigger::Response& rs);
  bool on_disable(std_srvs::Trigger::Request& rq, std_srvs::Trigger::Response& rs);
  bool on_get_memory(virtual_triaxial::GetMemory::Request& rq, virtual_triaxial::GetMemory::Response& rs);
  bool on_set_memory(virtual_triaxial::SetMemory::Request& rq, virtual_triaxial::SetMemory::Response& rs);
  bool controls(int axis) const { return mask_[axis]; }

  ::ros::NodeHandle nh_, pnh_;
  std::string strategy_name_, owner_;
  control::ServoParameters params_;  ///< in force (rates in 1/s once T0 is known)
  // dimensionless settings (parameters / live tuning)
  double gain_ = 0.5, ki_ = 0.0, kd_ = 0.0;
  double max_dimensionless_rate_ = 1e-4;
  double max_rate_change_ = 0.0;  ///< |delta rate| T0 per update
  double t0_ = 0.0;               ///< dem_node's T0 [s]; 0 until get_info answered
  double dem_max_dimensionless_rate_ = 0.0;  ///< dem_node's limit; 0 until known
  std::vector<int> axes_;
  control::AxisMask mask_{false, false, false};
  std::unique_ptr<control::ServoStrategy> strategy_;
  TargetRamp ramp_;
  bool enabled_ = true, claimed_ = false;
  double last_time_ = 0.0;   ///< simulation time of the newest Stress [s]
  std::uint64_t last_tick_ = 0;  ///< tick of the newest Stress
  bool has_tick_ = false;
  std::uint64_t claim_tick_ = 0;  ///< dem_node's tick when our claim took effect
  /// The newest state received while enabled and not claimed: after a claim
  /// whose first answer was lost, dem_node already waits on us for it.
  virtual_triaxial::Stress::ConstPtr pending_;
  std::string last_wait_reason_;

  /// Held by every callback: the stress callback may run in another thread.
  std::recursive_mutex mutex_;
  std::unique_ptr<InlineCallbackQueue> express_;  ///< stress callback queue when inline
  ::ros::Subscriber stress_sub_;
  ::ros::Publisher command_pub_, state_pub_;
  ::ros::ServiceClient info_client_, claim_client_, release_client_;
  std::vector<::ros::ServiceServer> services_;
  ::ros::WallTimer retry_timer_;
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<virtual_triaxial::ServoConfig>> reconfigure_;
};

}  // namespace vt::ros
