// bag_recorder: every topic into rosbag files, with deep queues (see
// ros/bag_recorder.h).
//   rosrun virtual_triaxial bag_recorder -O PREFIX [--split-mb 512]
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <string>

#include <ros/callback_queue.h>
#include <ros/ros.h>

#include "virtual_triaxial/ros/bag_recorder.h"

namespace {
volatile std::sig_atomic_t g_stop = 0;  // set by SIGINT / SIGTERM (signal handlers need a global)
void on_signal(int) { g_stop = 1; }
}  // namespace

int main(int argc, char** argv) {
  // Own signal handling: on SIGINT the queued messages are still written
  // before the files are closed (ros::spin would drop them).
  ros::init(argc, argv, "bag_recorder", ros::init_options::NoSigintHandler);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::string prefix;
  double split_mb = 512.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "-O" || a == "--output") && i + 1 < argc) {
      prefix = argv[++i];
    } else if (a == "--split-mb" && i + 1 < argc) {
      split_mb = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: bag_recorder -O PREFIX [--split-mb MB]  (unknown argument: %s)\n", a.c_str());
      return 2;
    }
  }
  if (!(split_mb > 0.0)) {
    std::fprintf(stderr, "bag_recorder: --split-mb: must be > 0\n");
    return 2;
  }
  ros::NodeHandle nh;
  try {
    vt::ros::BagRecorder rec(nh, prefix, static_cast<std::uint64_t>(split_mb * 1024.0 * 1024.0));
    ros::NodeHandle pnh("~");
    rec.advertise_split(pnh);
    ros::CallbackQueue* queue = ros::getGlobalCallbackQueue();
    while (!g_stop && ros::ok()) queue->callAvailable(ros::WallDuration(0.1));
    while (!queue->isEmpty()) queue->callAvailable(ros::WallDuration(0));  // drain
    ROS_INFO("bag_recorder: %llu messages on %zu topics", static_cast<unsigned long long>(rec.messages()),
             rec.topics());
  } catch (const std::exception& e) {
    ROS_FATAL("bag_recorder: %s", e.what());
    return 2;
  }
  return 0;
}
