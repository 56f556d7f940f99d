// Live tuning of dem_node with dynamic_reconfigure (cfg/Dem.cfg): the mass
// damping of the specimen (dem/mass_damping.h), like the set_damping service.
//
//   damping_model  "OD" | "ND" (case-insensitive; stored upper case)
//   damping_ratio  xi [-], finite and >= 0
//
// Service ~set_parameters and topics ~parameter_updates /
// ~parameter_descriptions in dem_node's private namespace (/dem_node/...).
// The server lives on dem_node's private NodeHandle, whose callback queue is
// the node's own queue_, so a change is applied only where dem_node serves
// callbacks: between two control ticks (never inside the publish_every DEM
// steps of a tick); it acts from the next tick on.
// The config always shows the simulation's current damping: sync() after a
// load_sample (which restores the file's values / the node's overrides) or a
// set_damping call. An invalid value is refused with a ROS_WARN naming the
// field and the old value kept (the reply and ~parameter_updates, which
// rosbag records, show the values in force); every accepted change is logged
// with ROS_INFO.
// dynamic_reconfigure mirrors the config to the parameters ~damping_model /
// ~damping_ratio, so a dem_node restarted on the same master applies the
// tuned damping as its override.
#pragma once

#include <cstdint>
#include <functional>

#include <boost/thread/recursive_mutex.hpp>
#include <dynamic_reconfigure/server.h>
#include <ros/node_handle.h>

#include "virtual_triaxial/DemConfig.h"
#include "virtual_triaxial/dem/simulation.h"

namespace vt::ros {

class DemReconfigure {
 public:
  /// pnh: dem_node's private handle (with the node's callback queue);
  /// sim: the current simulation (load_sample replaces it), never null.
  DemReconfigure(const ::ros::NodeHandle& pnh, std::function<dem::Simulation*()> sim);

  /// Makes the config (and ~parameter_updates) show the simulation's damping.
  void sync();

 private:
  void on_reconfigure(virtual_triaxial::DemConfig& config, std::uint32_t level);

  std::function<dem::Simulation*()> sim_;
  boost::recursive_mutex mutex_;  // declared before server_, which uses it
  dynamic_reconfigure::Server<virtual_triaxial::DemConfig> server_;
};

}  // namespace vt::ros
