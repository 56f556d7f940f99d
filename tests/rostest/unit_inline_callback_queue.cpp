// InlineCallbackQueue without a master: a callback runs at once in the
// delivering thread when the node's mutex is free, and goes to the node's
// own queue (served later by the node's thread) when the node is busy.
#include <atomic>
#include <mutex>
#include <thread>

#include <boost/make_shared.hpp>
#include <gtest/gtest.h>
#include <ros/callback_queue.h>

#include "virtual_triaxial/ros/inline_callback_queue.h"

using vt::ros::InlineCallbackQueue;

namespace {

/// Records the thread it ran in.
class Probe : public ros::CallbackInterface {
 public:
  CallResult call() override {
    ran_in = std::this_thread::get_id();
    ++calls;
    return Success;
  }
  std::thread::id ran_in;
  std::atomic<int> calls{0};
};

}  // namespace

TEST(InlineCallbackQueue, RunsTheCallbackInTheDeliveringThreadWhenTheNodeIsFree) {
  ros::CallbackQueue own;
  std::recursive_mutex node;
  InlineCallbackQueue q(own, &node);
  auto p = boost::make_shared<Probe>();
  q.addCallback(p, 1);
  EXPECT_EQ(p->calls, 1);
  EXPECT_EQ(p->ran_in, std::this_thread::get_id());
  EXPECT_TRUE(own.isEmpty()) << "nothing left for the node's own thread";
}

TEST(InlineCallbackQueue, DefersToTheNodesQueueWhileTheNodeIsBusyInAnotherThread) {
  ros::CallbackQueue own;
  std::recursive_mutex node;
  InlineCallbackQueue q(own, &node);
  auto p = boost::make_shared<Probe>();
  std::atomic<bool> locked{false}, release{false};
  std::thread busy([&] {  // the node's thread inside a (blocking) callback
    const std::lock_guard<std::recursive_mutex> lock(node);
    locked = true;
    while (!release) std::this_thread::yield();
  });
  while (!locked) std::this_thread::yield();
  q.addCallback(p, 1);  // must not wait for the busy node
  EXPECT_EQ(p->calls, 0);
  EXPECT_FALSE(own.isEmpty());
  release = true;
  busy.join();
  own.callAvailable(ros::WallDuration(0));  // the node's thread serves it later
  EXPECT_EQ(p->calls, 1);
}

TEST(InlineCallbackQueue, WithoutANodeMutexEveryCallbackRunsInline) {
  ros::CallbackQueue own;
  InlineCallbackQueue q(own, nullptr);
  auto p = boost::make_shared<Probe>();
  std::thread other([&] { q.addCallback(p, 7); });
  const std::thread::id other_id = other.get_id();
  other.join();
  EXPECT_EQ(p->calls, 1);
  EXPECT_EQ(p->ran_in, other_id);
  EXPECT_TRUE(own.isEmpty());
}
