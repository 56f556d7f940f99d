// rate_controller_node: the axial strain-rate controller of the virtual rig
// (issue 16), swappable like the servo. A thin adapter between ROS and
// control::RateStrategy (control/rate_strategy.h: fixed, predicted, adaptive).
//
// Parameters (private, `~`):
//   owner    the node's name; the name used with claim_axes
//
// Services, in the node's PRIVATE namespace (e.g. /rate_controller/configure):
//   configure (ConfigureRate.srv)  the law of the next stage: strategy, axis,
//             first rate [1/s], T0, I_QS and the adaptive settings; refused
//             (success false, message "<field>: <reason>") when bad or while
//             enabled
//   enable    (std_srvs/Trigger)   claims the axis at dem_node's current tick;
//             fails (success false) when the claim is refused or dem_node does
//             not answer. dem_node keeps the axis at its open-loop rate until
//             our first command (axis_arbiter.h), so the protocol node sets
//             that to the first rate before enabling
//   disable   (std_srvs/Trigger)   releases the axis (open loop at rate 0)
//   get_memory / set_memory (GetMemory.srv / SetMemory.srv)  the strategy's
//             memory (control::RateStrategy::memory()) for a rig checkpoint
//             and its resume; set_memory only while enabled
//
// Wiring (relative to the node's namespace, i.e. the rig's): subscribes
// `moment_index`, publishes `cell_command` (latched, like the servo's) and
// `rate_state` (RateState.msg), calls dem_node's `claim_axes`, `release_axes`.
//
// Per MomentIndex message of tick k after the claim: rate = strategy.update(
// {I_mom_k, I_QS}), a CellCommand with tick k for the axis, a RateState.
// The protocol node's stage judge runs the same law on the same I_mom
// (protocol/stage_judge.h), so triax_run and the rig take the same decisions
// tick for tick; the judge's summary uses the rates dem_node applied.
// Refusals name the field; no ROS time is used.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <ros/ros.h>
#include <std_srvs/Trigger.h>

#include "virtual_triaxial/ConfigureRate.h"
#include "virtual_triaxial/GetMemory.h"
#include "virtual_triaxial/SetMemory.h"
#include "virtual_triaxial/MomentIndex.h"
#include "virtual_triaxial/control/rate_strategy.h"
#include "virtual_triaxial/ros/inline_callback_queue.h"

namespace vt::ros {

class RateControllerNode {
 public:
  /// inline_index: run the moment_index callback in the thread that delivers
  /// it (the nodelet rig: dem_node's), under the node's mutex.
  RateControllerNode(const ::ros::NodeHandle& nh, const ::ros::NodeHandle& pnh, bool inline_index = false);

 private:
  void on_index(const virtual_triaxial::MomentIndex::ConstPtr& msg);
  bool on_configure(virtual_triaxial::ConfigureRate::Request& rq, virtual_triaxial::ConfigureRate::Response& rs);
  bool on_enable(std_srvs::Trigger::Request& rq, std_srvs::Trigger::Response& rs);
  bool on_disable(std_srvs::Trigger::Request& rq, std_srvs::Trigger::Response& rs);
  bool on_get_memory(virtual_triaxial::GetMemory::Request& rq, virtual_triaxial::GetMemory::Response& rs);
  bool on_set_memory(virtual_triaxial::SetMemory::Request& rq, virtual_triaxial::SetMemory::Response& rs);
  std::string release();

  ::ros::NodeHandle nh_, pnh_;
  std::string owner_;
  std::unique_ptr<control::RateStrategy> strategy_;
  double rate0_ = 0.0, t0_ = 0.0, threshold_ = 1e-3;
  int axis_ = 2;
  bool claimed_ = false;
  std::uint64_t claim_tick_ = 0;

  std::recursive_mutex mutex_;  ///< held by every callback (the index callback may run in another thread)
  std::unique_ptr<InlineCallbackQueue> express_;
  ::ros::Subscriber index_sub_;
  ::ros::Publisher command_pub_, state_pub_;
  ::ros::ServiceClient claim_client_, release_client_;
  std::vector<::ros::ServiceServer> services_;
};

}  // namespace vt::ros
