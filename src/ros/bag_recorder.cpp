// BagRecorder: see bag_recorder.h.
#include "virtual_triaxial/ros/bag_recorder.h"

#include <cstdio>
#include <stdexcept>
#include <vector>

namespace vt::ros {

BagRecorder::BagRecorder(const ::ros::NodeHandle& nh, std::string prefix, std::uint64_t split_bytes)
    : nh_(nh), prefix_(std::move(prefix)), split_bytes_(split_bytes) {
  if (prefix_.empty()) throw std::invalid_argument("output: the bag file prefix is empty");
  if (split_bytes_ == 0) throw std::invalid_argument("split: must be > 0 bytes");
  open_next();
  poll_topics();
  poll_timer_ = nh_.createWallTimer(::ros::WallDuration(0.2), [this](const ::ros::WallTimerEvent&) { poll_topics(); });
}

BagRecorder::~BagRecorder() { close_current(); }

void BagRecorder::poll_topics() {
  ::ros::master::V_TopicInfo topics;
  if (!::ros::master::getTopics(topics)) return;
  for (const ::ros::master::TopicInfo& t : topics) {
    if (subs_.count(t.name)) continue;
    const std::string name = t.name;
    ::ros::SubscribeOptions so;
    so.init<topic_tools::ShapeShifter>(
        name, kQueue, [this, name](const ::ros::MessageEvent<const topic_tools::ShapeShifter>& e) { on_message(name, e); });
    so.transport_hints = ::ros::TransportHints().tcpNoDelay();
    subs_[name] = nh_.subscribe(so);
  }
}

void BagRecorder::on_message(const std::string& topic, const ::ros::MessageEvent<const topic_tools::ShapeShifter>& e) {
  ::ros::Time t = ::ros::Time::now();
  if (t < ::ros::TIME_MIN) t = ::ros::TIME_MIN;
  if (bag_->getSize() > split_bytes_) {
    close_current();
    open_next();
  }
  bag_->write(topic, t, e.getConstMessage(), e.getConnectionHeaderPtr());
  ++messages_;
}

void BagRecorder::open_next() {
  path_ = prefix_ + "_" + std::to_string(file_index_) + ".bag";
  bag_ = std::make_unique<rosbag::Bag>();
  bag_->open(path_ + ".active", rosbag::bagmode::Write);
}

void BagRecorder::close_current() {
  if (!bag_) return;
  bag_->close();
  bag_.reset();
  if (std::rename((path_ + ".active").c_str(), path_.c_str()) != 0)
    ROS_ERROR("bag_recorder: cannot rename %s.active to %s", path_.c_str(), path_.c_str());
  ++file_index_;
}

}  // namespace vt::ros
