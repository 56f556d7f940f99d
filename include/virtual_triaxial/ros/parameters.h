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

/// A whole-number parameter; throws naming "~name" when it is set but not one
/// (e.g. a launch argument `publish_every:=abc`, which ros::param would
/// silently replace by its default).
inline std::optional<int> optional_int(const ::ros::NodeHandle& pnh, const std::string& name) {
  int i;
  if (pnh.getParam(name, i)) return i;
  if (pnh.hasParam(name)) throw std::invalid_argument("~" + name + ": must be a whole number");
  return std::nullopt;
}

/// A true/false parameter; throws naming "~name" when it is set but not one.
inline std::optional<bool> optional_bool(const ::ros::NodeHandle& pnh, const std::string& name) {
  bool b;
  if (pnh.getParam(name, b)) return b;
  if (pnh.hasParam(name)) throw std::invalid_argument("~" + name + ": must be true or false");
  return std::nullopt;
}

}  // namespace vt::ros
