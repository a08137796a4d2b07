// se3_interpolation_node: initialise, construct the node, spin.
#include <ros/ros.h>

#include "se3_interpolation/ros/interpolation_node.h"

int main(int argc, char** argv)
{
  ros::init(argc, argv, "se3_interpolation_node");
  se3_interpolation::InterpolationNode node(ros::NodeHandle(), ros::NodeHandle("~"));
  ros::spin();
  return 0;
}
