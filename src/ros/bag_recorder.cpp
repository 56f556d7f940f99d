// BagRecorder: see bag_recorder.h.
#include "virtual_triaxial/ros/bag_recorder.h"

#include <cstdio>
#include <stdexcept>
#include <vector>

#include <rosgraph_msgs/Clock.h>

#include "virtual_triaxial/CellCommand.h"
#include "virtual_triaxial/Fabric.h"
#include "virtual_triaxial/KineticEnergy.h"
#include "virtual_triaxial/MomentIndex.h"
#include "virtual_triaxial/ProtocolStatus.h"
#include "virtual_triaxial/ServoState.h"
#include "virtual_triaxial/Strain.h"
#include "virtual_triaxial/Stress.h"

namespace vt::ros {

BagRecorder::BagRecorder(const ::ros::NodeHandle& nh, std::string prefix, std::uint64_t split_bytes,
                         bool typed_rig_topics)
    : nh_(nh), prefix_(std::move(prefix)), split_bytes_(split_bytes) {
  if (prefix_.empty()) throw std::invalid_argument("output: the bag file prefix is empty");
  if (split_bytes_ == 0) throw std::invalid_argument("split: must be > 0 bytes");
  if (typed_rig_topics) {
    subscribe_typed<virtual_triaxial::Stress>("stress");
    subscribe_typed<virtual_triaxial::Strain>("strain");
    subscribe_typed<virtual_triaxial::MomentIndex>("moment_index");
    subscribe_typed<virtual_triaxial::KineticEnergy>("kinetic_energy");
    subscribe_typed<virtual_triaxial::Fabric>("fabric");
    subscribe_typed<virtual_triaxial::ServoState>("servo_state");
    subscribe_typed<virtual_triaxial::CellCommand>("cell_command");
    subscribe_typed<virtual_triaxial::ProtocolStatus>("protocol_status");
    subscribe_typed<rosgraph_msgs::Clock>("/clock");
  }
  poll_topics();
  open_next();  // last: the file's appearance tells that the subscriptions exist
  poll_timer_ = nh_.createWallTimer(::ros::WallDuration(0.2), [this](const ::ros::WallTimerEvent&) { poll_topics(); });
}

BagRecorder::~BagRecorder() { close_current(); }

void BagRecorder::advertise_split(::ros::NodeHandle& pnh) {
  split_srv_ = pnh.advertiseService<std_srvs::Trigger::Request, std_srvs::Trigger::Response>(
      "split", [this](std_srvs::Trigger::Request&, std_srvs::Trigger::Response& rs) {
        rs.success = !failed_ && bag_ != nullptr;
        if (!rs.success) {
          rs.message = "not recording (a write failed)";
          return true;
        }
        const std::string closed = path_;
        try {
          close_current();
          open_next();
        } catch (const std::exception& e) {
          failed_ = true;
          rs.success = false;
          rs.message = std::string("split: ") + e.what() + "; recording stopped";
          ROS_ERROR("bag_recorder: %s", rs.message.c_str());
          return true;
        }
        rs.message = "closed " + closed + " after " + std::to_string(messages_) + " messages; now " + path_ + ".active";
        return true;
      });
}

void BagRecorder::poll_topics() {
  ::ros::master::V_TopicInfo topics;
  if (!::ros::master::getTopics(topics)) return;
  for (const ::ros::master::TopicInfo& t : topics) {
    if (subs_.count(t.name)) continue;
    const std::string name = t.name;
    ::ros::SubscribeOptions so;
    so.init<topic_tools::ShapeShifter>(name, kQueue,
                                       [this, name](const ::ros::MessageEvent<const topic_tools::ShapeShifter>& e) {
                                         on_message<topic_tools::ShapeShifter>(name, e);
                                       });
    so.transport_hints = ::ros::TransportHints().tcpNoDelay();
    subs_[name] = nh_.subscribe(so);
  }
}

template <class M>
void BagRecorder::subscribe_typed(const std::string& name) {
  const std::string topic = nh_.resolveName(name);
  ::ros::SubscribeOptions so;
  so.init<M>(topic, kQueue, [this, topic](const ::ros::MessageEvent<const M>& e) { on_message<M>(topic, e); });
  so.transport_hints = ::ros::TransportHints().tcpNoDelay();
  subs_[topic] = nh_.subscribe(so);
}

template <class M>
void BagRecorder::on_message(const std::string& topic, const ::ros::MessageEvent<const M>& e) {
  if (failed_) return;
  try {
    split_if_full();
    bag_->write(topic, stamp(), e.getConstMessage(), e.getConnectionHeaderPtr());
    ++messages_;
  } catch (const std::exception& ex) {
    // A full disk (or any write error) stops the recording, never the rig.
    failed_ = true;
    ROS_ERROR("bag_recorder: cannot write %s.active: %s; recording stopped after %llu messages", path_.c_str(),
              ex.what(), static_cast<unsigned long long>(messages_));
    try {
      close_current();
    } catch (const std::exception& ex2) {
      ROS_ERROR("bag_recorder: cannot close %s.active: %s (`rosbag reindex` recovers it)", path_.c_str(),
                ex2.what());
      bag_.reset();
    }
  }
}

::ros::Time BagRecorder::stamp() const {
  const ::ros::Time t = ::ros::Time::now();
  return t < ::ros::TIME_MIN ? ::ros::TIME_MIN : t;
}

void BagRecorder::split_if_full() {
  if (bag_->getSize() <= split_bytes_) return;
  close_current();
  open_next();
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
