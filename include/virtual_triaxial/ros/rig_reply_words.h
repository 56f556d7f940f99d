// The words of rig service answers that another node acts on, each with one
// home, so the node that says them and the node that reads them cannot
// drift apart. Plain C++ (no ROS include): AxisArbiter, the servo node, the
// protocol session and the controllers' release (idempotent_call.h) share
// it. The Python nodes hold the same words in scripts/rig_service_calls.py
// (OWNER_REFUSAL, NOT_CLAIMED_YET), checked equal to these by
// tests/rostest/unit_rig_reply_words.cpp.
#pragma once

#include <string>

namespace vt::ros::reply_words {

/// How AxisArbiter's refusals of a request about the caller itself begin:
/// they name the field "owner" (an empty owner, an owner of no axis). A
/// repeated release_axes refused so means the first call, whose answer was
/// lost, released the axes (idempotent_call.h).
inline constexpr char kOwnerRefusal[] = "owner:";
/// What a servo's ~enable answer says while its claim of the cell axes is
/// pending (servo_controller_node.h); the protocol session asks ~enable
/// again while it says so (ProtocolSession::await_controllers).
inline constexpr char kNotClaimedYet[] = "not claimed yet";

/// An AxisArbiter refusal about the owner: "owner: <reason>".
inline std::string owner_refusal(const std::string& reason) { return std::string(kOwnerRefusal) + " " + reason; }
inline bool is_owner_refusal(const std::string& message) { return message.rfind(kOwnerRefusal, 0) == 0; }

/// A servo's ~enable answer while its claim is pending, `why` the claim's
/// last refusal or failure: "enabled; not claimed yet (<why>), retrying".
inline std::string enabled_not_claimed_yet(const std::string& why) {
  return std::string("enabled; ") + kNotClaimedYet + " (" + why + "), retrying";
}
inline bool says_not_claimed_yet(const std::string& message) {
  return message.find(kNotClaimedYet) != std::string::npos;
}

}  // namespace vt::ros::reply_words
