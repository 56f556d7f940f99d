// InlineCallbackQueue: see inline_callback_queue.h.
#include "virtual_triaxial/ros/inline_callback_queue.h"

#include <ros/callback_queue_interface.h>

namespace vt::ros {

void InlineCallbackQueue::addCallback(const ::ros::CallbackInterfacePtr& callback, std::uint64_t owner_id) {
  std::unique_lock<std::recursive_mutex> lock;
  if (mutex_) {
    lock = std::unique_lock<std::recursive_mutex>(*mutex_, std::try_to_lock);
    if (!lock.owns_lock()) {  // the node is busy in another callback: its own thread serves this one
      fallback_.addCallback(callback, owner_id);
      return;
    }
  }
  if (!callback->ready() || callback->call() == ::ros::CallbackInterface::TryAgain)
    fallback_.addCallback(callback, owner_id);
}

}  // namespace vt::ros
