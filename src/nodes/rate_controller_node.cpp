// rate_controller_node: the axial strain-rate controller (see ros/rate_controller_node.h).
#include <ros/ros.h>

#include "virtual_triaxial/ros/rate_controller_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "rate_controller_node");
  ros::NodeHandle nh, pnh("~");
  try {
    vt::ros::RateControllerNode node(nh, pnh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("rate_controller_node: %s", e.what());
    return 2;
  }
  return 0;
}
