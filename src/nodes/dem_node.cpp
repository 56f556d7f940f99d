// dem_node: the DEM specimen and cell of the virtual rig (see ros/dem_node.h).
#include <ros/ros.h>

#include "virtual_triaxial/ros/dem_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "dem_node");
  // Handles held here so that ROS (and its logging) stays up while an
  // exception from the constructor is reported.
  ros::NodeHandle nh, pnh("~");
  try {
    vt::ros::DemNode node(nh, pnh);
    node.spin();
  } catch (const std::exception& e) {
    ROS_FATAL("dem_node: %s", e.what());
    return 2;
  }
  return 0;
}
