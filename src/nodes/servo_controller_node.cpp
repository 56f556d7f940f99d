// servo_controller_node: the cell-pressure controller (see ros/servo_controller_node.h).
#include <ros/ros.h>

#include "virtual_triaxial/ros/servo_controller_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "servo_controller_node");
  // Handles held here so that ROS (and its logging) stays up while an
  // exception from the constructor is reported.
  ros::NodeHandle nh, pnh("~");
  try {
    vt::ros::ServoControllerNode node(nh, pnh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("servo_controller_node: %s", e.what());
    return 2;
  }
  return 0;
}
