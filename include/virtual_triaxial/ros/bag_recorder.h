// bag_recorder: records every topic of the rig into rosbag files, without
// losing messages when it falls behind for a while.
//
// Why not `rosbag record -a`: it subscribes with 100-message queues, so a
// recorder starved of CPU for 100 control ticks (a fast rig on 2 busy cores:
// ~0.2 s) drops messages. This recorder subscribes with deep queues
// (kQueue messages per topic, about a minute of control ticks) and writes in
// its own spinner thread; the rig's publishers keep 1000 messages per
// subscriber as well. The files are ordinary bags (rosbag::Bag, connection
// headers kept, so latched topics stay latched on playback): rosbag play,
// rosbag info, the Python rosbag API and scripts/bag_report.py read them.
//
// Topics: every topic the master lists, polled every 0.2 s, so topics that
// appear later are recorded too (from the poll that sees them on). Message
// time = receipt time ros::Time::now() (simulation time on use_sim_time,
// at least ros::TIME_MIN); every rig message also carries its exact
// simulation time and tick in its header.
// In the nodelet rig the recorder is a nodelet in the rig's process
// (virtual_triaxial/BagRecorderNodelet): the rig's own topics (the five
// state topics, servo_state, cell_command, protocol_status, /clock) are
// subscribed with their types, so dem_node hands them over as pointers and
// the serialisation happens in the recorder's thread, not in the lockstep
// loop; every other topic as above.
// Files: <prefix>_<k>.bag, k = 0, 1, ...; a new file starts when the current
// one exceeds split_bytes. A file is written as <name>.active and renamed
// when closed (on shutdown: SIGINT), as rosbag does.
// Service ~split (std_srvs/Trigger, advertise_split()): close the current
// file now and go on in the next one, so that everything received so far is
// in a closed, indexed bag. test_protocol_node calls it at every checkpoint
// of a test (dem_node paused): a kill -9 afterwards loses no tick up to the
// checkpoint (a rosbag file keeps its last chunk in memory until it is
// closed), and `run_triaxial.sh --resume` records the ticks after it.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <rosbag/bag.h>
#include <topic_tools/shape_shifter.h>

namespace vt::ros {

class BagRecorder {
 public:
  static constexpr std::uint32_t kQueue = 100000;  ///< subscriber queue per topic [messages]

  /// typed_rig_topics: subscribe the rig's own topics with their message
  /// types (no serialisation in the publisher's thread within one process).
  BagRecorder(const ::ros::NodeHandle& nh, std::string prefix, std::uint64_t split_bytes,
              bool typed_rig_topics = false);
  ~BagRecorder();  ///< closes the current file
  BagRecorder(const BagRecorder&) = delete;
  BagRecorder& operator=(const BagRecorder&) = delete;

  /// Advertises ~split on `pnh` (the node's private handle, on the queue that
  /// delivers the messages, so a split follows the messages queued before it).
  void advertise_split(::ros::NodeHandle& pnh);
  std::uint64_t messages() const { return messages_; }
  std::size_t topics() const { return subs_.size(); }
  int files() const { return file_index_ + (bag_ ? 1 : 0); }

 private:
  void poll_topics();
  template <class M>
  void subscribe_typed(const std::string& name);
  template <class M>
  void on_message(const std::string& topic, const ::ros::MessageEvent<const M>& e);
  ::ros::Time stamp() const;  ///< receipt time, at least ros::TIME_MIN
  void split_if_full();
  void open_next();
  void close_current();

  ::ros::NodeHandle nh_;
  std::string prefix_;
  std::uint64_t split_bytes_;
  std::map<std::string, ::ros::Subscriber> subs_;
  std::unique_ptr<rosbag::Bag> bag_;
  std::string path_;      ///< current file (without .active)
  int file_index_ = 0;    ///< files closed so far
  std::uint64_t messages_ = 0;
  bool failed_ = false;   ///< a write failed (full disk): recording stopped
  ::ros::WallTimer poll_timer_;
  ::ros::ServiceServer split_srv_;
};

}  // namespace vt::ros
