// Small helpers shared by the rostest test nodes (header-only): wall-clock
// polling (the rig runs on simulation time, which stands still while
// dem_node is paused) and service calls that wait for the service first,
// made again when their answer is lost if repeating them changes nothing.
#pragma once

#include <functional>
#include <string>

#include <ros/ros.h>

#include "virtual_triaxial/ros/idempotent_call.h"

namespace vt::rostest {

inline bool starts_with(const std::string& s, const std::string& p) { return s.compare(0, p.size(), p) == 0; }

/// Polls `pred` every 20 ms of WALL time; false if it still fails after `seconds`.
inline bool wait_until(const std::function<bool()>& pred, double seconds) {
  const ::ros::WallTime end = ::ros::WallTime::now() + ::ros::WallDuration(seconds);
  while (::ros::ok() && ::ros::WallTime::now() < end) {
    if (pred()) return true;
    ::ros::WallDuration(0.02).sleep();
  }
  return pred();
}

/// Waits up to `seconds` (wall) for service `name`, then calls it.
template <class S>
bool call_service(const std::string& name, S& srv, double seconds) {
  if (!wait_until([&] { return ::ros::service::exists(name, false); }, seconds)) return false;
  return ::ros::service::call(name, srv);
}

/// call_service for a request whose repetition changes nothing (get_info,
/// pause): made again when its answer is lost after the server ran it
/// (ros/ros_comm#1976; vt::ros::call_idempotent, the controllers' policy).
/// A request that acts again when repeated (step) takes call_service.
template <class S>
bool call_service_again(const std::string& name, S& srv, double seconds) {
  if (!wait_until([&] { return ::ros::service::exists(name, false); }, seconds)) return false;
  ::ros::NodeHandle nh;
  ::ros::ServiceClient client = nh.serviceClient<S>(name);
  return vt::ros::call_idempotent(client, srv) > 0;
}

}  // namespace vt::rostest
