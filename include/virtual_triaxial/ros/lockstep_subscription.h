// The subscription a lockstep controller answers from (the servo to
// `stress`, the rate controller to `moment_index`): TCP_NODELAY, and with
// `inline_delivery` through an InlineCallbackQueue (inline_callback_queue.h)
// so the answer for tick k leaves in the publisher's thread. One home for
// that choice, shared by every controller node.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include <ros/ros.h>

#include "virtual_triaxial/ros/inline_callback_queue.h"

namespace vt::ros {

/// Subscribes `on_msg(const typename Msg::ConstPtr&)` to `topic` (resolved
/// in `nh`); with `inline_delivery` the queue is created in `express` (kept
/// by the node for the subscription's lifetime) and runs the callback under
/// `node_mutex` when free.
template <class Msg, class Fn>
::ros::Subscriber subscribe_lockstep(::ros::NodeHandle& nh, const std::string& topic, Fn on_msg,
                                     bool inline_delivery, std::recursive_mutex& node_mutex,
                                     std::unique_ptr<InlineCallbackQueue>& express) {
  ::ros::SubscribeOptions so;
  so.init<Msg>(nh.resolveName(topic), 100, std::move(on_msg));
  so.transport_hints = ::ros::TransportHints().tcpNoDelay();
  if (inline_delivery) {
    express = std::make_unique<InlineCallbackQueue>(*nh.getCallbackQueue(), &node_mutex);
    so.callback_queue = express.get();
  }
  return nh.subscribe(so);
}

}  // namespace vt::ros
