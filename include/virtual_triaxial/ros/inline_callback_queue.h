// A callback queue that runs each callback at once, in the thread that
// delivers it, instead of waking the node's own spinner thread.
//
// For a subscriber in the same process as the publisher (the nodelet rig)
// that thread is the publisher's, inside publish(); for a subscriber in
// another process it is roscpp's network thread. A lockstep round trip
// (dem_node publishes tick k, a controller answers with its command for
// tick k) then needs no thread wake-up at all in the nodelet rig, and one
// less in separate processes.
//
// Use it only for callbacks that never block (no service calls, no waiting),
// since they run in someone else's thread. With a node mutex, the callback
// runs under that mutex when it is free; when the node is busy in another
// callback (its own thread holds the mutex) the callback goes to the node's
// own queue instead, to be served by that thread, so a node that makes a
// blocking call while holding the mutex never stalls the publisher.
#pragma once

#include <cstdint>
#include <mutex>

#include <ros/callback_queue_interface.h>

namespace vt::ros {

class InlineCallbackQueue : public ::ros::CallbackQueueInterface {
 public:
  /// fallback: the node's own queue; node_mutex: held while a callback of the
  /// node runs (nullptr: the callbacks are thread-safe on their own).
  InlineCallbackQueue(::ros::CallbackQueueInterface& fallback, std::recursive_mutex* node_mutex)
      : fallback_(fallback), mutex_(node_mutex) {}

  void addCallback(const ::ros::CallbackInterfacePtr& callback, std::uint64_t owner_id) override;
  void removeByID(std::uint64_t owner_id) override { fallback_.removeByID(owner_id); }

 private:
  ::ros::CallbackQueueInterface& fallback_;
  std::recursive_mutex* mutex_;
};

}  // namespace vt::ros
