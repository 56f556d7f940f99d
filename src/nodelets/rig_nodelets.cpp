// The three rig nodes as nodelets, so that the whole rig can run in one
// process (launch_equiv_scripts/protocol_rig.launch, nodelets:=true):
//
//   virtual_triaxial/DemNodelet            = dem_node
//   virtual_triaxial/ServoControllerNodelet = servo_controller_node
//   virtual_triaxial/RateControllerNodelet = rate_controller_node
//   virtual_triaxial/TestProtocolNodelet   = test_protocol_node
//   virtual_triaxial/BagRecorderNodelet    = bag_recorder (the entry script's recorder)
//
// Same classes, parameters, topics and services as the stand-alone nodes
// (ros/dem_node.h, ros/servo_controller_node.h, ros/test_protocol_node.h);
// only the transport of the lockstep loop changes: the state messages reach
// the servo and the protocol node as shared pointers (no serialisation, no
// TCP, no network thread), and a command reaches dem_node's queue directly.
// Nodes outside the manager (rosbag, a Python controller, rostopic) still
// connect over TCP as before, so controllers stay swappable.
//
// Threads: the DEM loop runs in its own thread (it never returns to a
// callback queue); the servo and the protocol node each serve their
// callbacks from their own queue in their own thread (as with ros::spin),
// not from the manager's shared worker pool, which would add a hand-off per
// message. The lockstep path needs no thread hand-off at all: the servo's
// stress callback and the protocol node's tick judgement run inline in
// dem_node's thread while it publishes (ros/inline_callback_queue.h), so
// both answers are already queued when dem_node starts to wait.
#include <atomic>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/callback_queue.h>
#include <ros/ros.h>

#include "virtual_triaxial/ros/bag_recorder.h"
#include "virtual_triaxial/ros/dem_node.h"
#include "virtual_triaxial/ros/rate_controller_node.h"
#include "virtual_triaxial/ros/servo_controller_node.h"
#include "virtual_triaxial/ros/test_protocol_node.h"

namespace vt::nodelets {

/// Runs a node's constructor; a bad parameter (a wrong launch argument of
/// protocol_rig.launch: same names, servo_X -> /servo/~X) is logged as the
/// stand-alone node logs it, "<node>: ~<param>: <what it takes>", before the
/// manager's bare "Failed to load nodelet".
template <class F>
void construct_or_report(const std::string& node, F&& construct) {
  try {
    construct();
  } catch (const std::exception& e) {
    ROS_FATAL("%s: %s", node.substr(node.rfind('/') + 1).c_str(), e.what());
    throw;
  }
}

/// dem_node: DemNode::spin() in a thread of its own; stop() on unload.
class DemNodelet : public nodelet::Nodelet {
 public:
  ~DemNodelet() override {
    if (node_) node_->stop();
    if (thread_.joinable()) thread_.join();
  }

 private:
  void onInit() override {
    construct_or_report(getName(), [&] {
      node_ = std::make_unique<vt::ros::DemNode>(getNodeHandle(), getPrivateNodeHandle());
    });
    thread_ = std::thread([this] { node_->spin(); });
  }
  std::unique_ptr<vt::ros::DemNode> node_;
  std::thread thread_;
};

/// A node class whose callbacks are served from its own queue by its own
/// thread (what ros::spin() does for the stand-alone node).
template <class Node>
class QueueThreadNodelet : public nodelet::Nodelet {
 public:
  ~QueueThreadNodelet() override {
    running_ = false;
    if (thread_.joinable()) thread_.join();
    node_.reset();  // before the queue it uses
  }

 private:
  void onInit() override {
    ::ros::NodeHandle nh = getNodeHandle(), pnh = getPrivateNodeHandle();
    nh.setCallbackQueue(&queue_);
    pnh.setCallbackQueue(&queue_);
    construct_or_report(getName(), [&] { node_ = make(nh, pnh); });
    thread_ = std::thread([this] {
      while (running_ && ::ros::ok()) queue_.callAvailable(::ros::WallDuration(0.05));
    });
  }
  virtual std::unique_ptr<Node> make(const ::ros::NodeHandle& nh, const ::ros::NodeHandle& pnh) {
    return std::make_unique<Node>(nh, pnh);
  }
  ::ros::CallbackQueue queue_;
  std::unique_ptr<Node> node_;
  std::atomic<bool> running_{true};
  std::thread thread_;
};

/// servo_controller_node; its stress callback runs inline in the thread
/// that publishes the stress (dem_node's), see ros/inline_callback_queue.h.
class ServoControllerNodelet : public QueueThreadNodelet<vt::ros::ServoControllerNode> {
  std::unique_ptr<vt::ros::ServoControllerNode> make(const ::ros::NodeHandle& nh,
                                                      const ::ros::NodeHandle& pnh) override {
    return std::make_unique<vt::ros::ServoControllerNode>(nh, pnh, true);
  }
};
/// rate_controller_node; its moment_index callback runs inline like the servo's.
class RateControllerNodelet : public QueueThreadNodelet<vt::ros::RateControllerNode> {
  std::unique_ptr<vt::ros::RateControllerNode> make(const ::ros::NodeHandle& nh,
                                                     const ::ros::NodeHandle& pnh) override {
    return std::make_unique<vt::ros::RateControllerNode>(nh, pnh, true);
  }
};
using TestProtocolNodelet = QueueThreadNodelet<vt::ros::TestProtocolNode>;

/// bag_recorder in the rig's process (ros/bag_recorder.h), with the rig's
/// topics typed. Private parameters: ~prefix (bag files <prefix>_<k>.bag,
/// required), ~split_mb (512). On unload it writes what is still queued,
/// then closes the file.
class BagRecorderNodelet : public nodelet::Nodelet {
 public:
  ~BagRecorderNodelet() override {
    running_ = false;
    if (thread_.joinable()) thread_.join();
    while (recorder_ && !queue_.isEmpty()) queue_.callAvailable(::ros::WallDuration(0));
    recorder_.reset();
  }

 private:
  void onInit() override {
    ::ros::NodeHandle nh = getNodeHandle(), pnh = getPrivateNodeHandle();
    nh.setCallbackQueue(&queue_);
    construct_or_report(getName(), [&] {
      std::string prefix;
      if (!pnh.getParam("prefix", prefix)) throw std::invalid_argument("~prefix: required (bag files <prefix>_<k>.bag)");
      const double split_mb = pnh.param("split_mb", 512.0);
      if (!(split_mb > 0.0)) throw std::invalid_argument("~split_mb: must be > 0");
      recorder_ = std::make_unique<vt::ros::BagRecorder>(
          nh, prefix, static_cast<std::uint64_t>(split_mb * 1024.0 * 1024.0), true);
      pnh.setCallbackQueue(&queue_);
      recorder_->advertise_split(pnh);
    });
    // Polls instead of waiting on the queue: a thread asleep on the queue
    // costs the publisher a wake-up call per message, and the recorder has
    // no latency to keep (its queues are deep).
    thread_ = std::thread([this] {
      while (running_ && ::ros::ok()) {
        queue_.callAvailable(::ros::WallDuration(0));
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
    });
  }
  ::ros::CallbackQueue queue_;
  std::unique_ptr<vt::ros::BagRecorder> recorder_;
  std::atomic<bool> running_{true};
  std::thread thread_;
};

}  // namespace vt::nodelets

PLUGINLIB_EXPORT_CLASS(vt::nodelets::DemNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(vt::nodelets::ServoControllerNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(vt::nodelets::RateControllerNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(vt::nodelets::TestProtocolNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(vt::nodelets::BagRecorderNodelet, nodelet::Nodelet)
