// test_protocol_node: the test operator (see ros/test_protocol_node.h).
#include <ros/ros.h>

#include "virtual_triaxial/ros/test_protocol_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "test_protocol_node");
  // Handles held here so that ROS (and its logging) stays up while an
  // exception from the constructor is reported.
  ros::NodeHandle nh, pnh("~");
  try {
    vt::ros::TestProtocolNode node(nh, pnh);
    ros::spin();  // the action executes in its own thread
  } catch (const std::exception& e) {
    ROS_FATAL("test_protocol_node: %s", e.what());
    return 2;
  }
  return 0;
}
