// Reading optional private parameters of the rig's nodes.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>

#include <ros/node_handle.h>

namespace vt::ros {

/// A number parameter (an integer in YAML, e.g. `1`, is accepted too); throws
/// std::invalid_argument naming "~name" when it is set but not a number.
inline std::optional<double> optional_double(const ::ros::NodeHandle& pnh, const std::string& name) {
  double d;
  if (pnh.getParam(name, d)) return d;
  int i;
  if (pnh.getParam(name, i)) return static_cast<double>(i);
  if (pnh.hasParam(name)) throw std::invalid_argument("~" + name + ": must be a number");
  return std::nullopt;
}

/// A string parameter; throws naming "~name" when it is set but not a string.
inline std::optional<std::string> optional_string(const ::ros::NodeHandle& pnh, const std::string& name) {
  std::string s;
  if (pnh.getParam(name, s)) return s;
  if (pnh.hasParam(name)) throw std::invalid_argument("~" + name + ": must be a string");
  return std::nullopt;
}

}  // namespace vt::ros
