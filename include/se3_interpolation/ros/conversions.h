// All conversions between ROS messages and the core types (tf2_eigen based).
#pragma once

#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Path.h>
#include <std_msgs/Header.h>
#include <trajectory_msgs/MultiDOFJointTrajectory.h>
#include <visualization_msgs/MarkerArray.h>

#include "se3_interpolation/GenerateTrajectory.h"
#include "se3_interpolation/planner/planner.h"

namespace se3_interpolation
{
Pose<double> fromPoseMsg(const geometry_msgs::Pose& msg);
geometry_msgs::Pose toPoseMsg(const Pose<double>& pose);
Twist fromTwistMsg(const geometry_msgs::Twist& msg);
geometry_msgs::Twist toTwistMsg(const Twist& twist);
geometry_msgs::Transform toTransformMsg(const Pose<double>& pose);

/// The core request from a service request (waypoints taken from `poses`).
TrajectoryRequest fromRequestMsg(const GenerateTrajectory::Request& msg, const std::vector<geometry_msgs::Pose>& poses);

/// nav_msgs/Path of the samples; each pose stamped header.stamp + sample time.
nav_msgs::Path toPathMsg(const TrajectoryResult& result, const std_msgs::Header& header);

/// One-joint MultiDOFJointTrajectory (transforms, velocities, accelerations, time_from_start).
trajectory_msgs::MultiDOFJointTrajectory toTrajectoryMsg(const TrajectoryResult& result, const std_msgs::Header& header,
                                                         const std::string& joint_name);

/// rviz markers: waypoints (spheres), the control polygon, the sampled path, the blend zones
/// (a translucent sphere of radius r_i at each blended corner, ns `blend_zones`) and
/// `axes` evenly spaced body axes (x red, y green, z blue) of length `axis_length` m.
/// The first marker deletes what an earlier trajectory drew.
visualization_msgs::MarkerArray toMarkerArray(const TrajectoryResult& result, const std::vector<Pose<double>>& waypoints,
                                              const std_msgs::Header& header, int axes, double axis_length);

}  // namespace se3_interpolation
