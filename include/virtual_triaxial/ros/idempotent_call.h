// A service call that is made again when its answer does not arrive.
//
// roscpp can lose the answer to a non-persistent service call after the
// server has run the request: the connection is closed before the client
// reads the answer (ros/ros_comm#1976), and ServiceClient::call returns
// false. A request whose repetition changes nothing can simply be made
// again: get_info, pause, resume, set_strain_rate, the controllers' enable
// and disable, and claim_axes, which answers a repeated claim with the first
// claim's tick (axis_arbiter.h). One home for that policy, shared by the
// controller nodes and the protocol session (the servers answer refusals
// with success = false, so a failed call is always a transport failure).
#pragma once

#include <functional>
#include <string>

#include <ros/ros.h>

#include "virtual_triaxial/ReleaseAxes.h"
#include "virtual_triaxial/ros/rig_reply_words.h"

namespace vt::ros {

struct CallRetry {
  int attempts = 3;     ///< calls in all, >= 1
  double pause = 0.05;  ///< wall seconds before each repeated call
};

/// Calls `client` until a call is answered or `policy.attempts` calls
/// failed; `before_retry(k)` runs before repeated call k (k >= 1). Returns
/// how many calls were made when one was answered, 0 when none was.
template <class Srv>
int call_idempotent(::ros::ServiceClient& client, Srv& srv, const CallRetry& policy = {},
                    const std::function<void(int)>& before_retry = {}) {
  for (int k = 0; k < policy.attempts; ++k) {
    if (k > 0) {
      if (before_retry) before_retry(k);
      ::ros::WallDuration(policy.pause).sleep();
    }
    if (client.call(srv)) return k + 1;
  }
  return 0;
}

/// release_axes made again when its answer is lost. `answered`: some call
/// was answered; `released`: the axes are free of the owner, also when the
/// repeated call is refused as the request of an owner of no axis (the
/// refusal names the field "owner", axis_arbiter.h: the lost call released
/// them); otherwise `refusal` is dem_node's message.
struct ReleaseAnswer {
  bool answered = false;
  bool released = false;
  std::string refusal;
  /// What a controller reports of it: "" when released, or when it held no
  /// claim (it asks anyway, in case dem_node lists one whose answer was
  /// lost; then a refusal or silence means none, as it thinks).
  std::string why(bool held) const {
    if (released || !held) return "";
    return answered ? "release_axes refused: " + refusal : "release_axes: dem_node does not answer";
  }
};
inline ReleaseAnswer call_release_axes(::ros::ServiceClient& client, virtual_triaxial::ReleaseAxes& rel) {
  ReleaseAnswer a;
  const int calls = call_idempotent(client, rel);
  a.answered = calls > 0;
  if (!a.answered) return a;
  a.released = rel.response.success || (calls > 1 && reply_words::is_owner_refusal(rel.response.message));
  if (!a.released) a.refusal = rel.response.message;
  return a;
}

}  // namespace vt::ros
