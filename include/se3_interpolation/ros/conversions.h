// All conversions between ROS messages and the core types (tf2_eigen based).
#pragma once

#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Path.h>
#include <std_msgs/Header.h>
#include <trajectory_msgs/JointTrajectory.h>
#include <trajectory_msgs/MultiDOFJointTrajectory.h>
#include <visualization_msgs/MarkerArray.h>

#include "se3_interpolation/GenerateTrajectory.h"
#include "se3_interpolation/GenerationStatus.h"
#include "se3_interpolation/execution/goal_trajectory.h"
#include "se3_interpolation/planner/planner.h"

namespace se3_interpolation
{
// In the style of tf2_eigen: overloads of fromMsg / toMsg by argument type; where one core type
// has several message forms (a pose as geometry_msgs/Pose or /Transform, a result as a path or a
// trajectory), the message is an output argument, returned by reference.

/// world_T_body from a geometry_msgs/Pose (quaternion x, y, z, w; not normalised here:
/// validatePose does that and refuses what is not nearly unit).
Pose<double> fromMsg(const geometry_msgs::Pose& msg);
geometry_msgs::Pose toMsg(const Pose<double>& pose);
/// A spatial twist (linear m/s, angular rad/s, the waypoints' frame), or its derivative.
Twist fromMsg(const geometry_msgs::Twist& msg);
geometry_msgs::Twist toMsg(const Twist& twist);
/// The pose as the transform parent_T_child (tf2's convention for the same pose).
geometry_msgs::Transform& toMsg(const Pose<double>& pose, geometry_msgs::Transform& out);
/// The pose of a transform parent_T_child (a tf2 lookup's), the quaternion kept as given.
Pose<double> fromMsg(const geometry_msgs::Transform& msg);

/// A goal's point from the first joint's transform, velocity and acceleration of a
/// MultiDOFJointTrajectory point (absent where the message has none; the caller checks that the
/// point has a transform and no second joint); time_from_start in s.
GoalPoint fromMsg(const trajectory_msgs::MultiDOFJointTrajectoryPoint& msg);

/// The core request from a service request (waypoints taken from `poses`: the request's own,
/// transformed into the waypoints' frame, then those of waypoint_frames).
TrajectoryRequest fromMsg(const GenerateTrajectory::Request& msg, const std::vector<geometry_msgs::Pose>& poses);

/// nav_msgs/Path of the samples; each pose stamped header.stamp + sample time.
nav_msgs::Path& toMsg(const TrajectoryResult& result, const std_msgs::Header& header, nav_msgs::Path& out);

/// One-joint MultiDOFJointTrajectory (transforms, velocities, accelerations, time_from_start).
trajectory_msgs::MultiDOFJointTrajectory& toMsg(const TrajectoryResult& result, const std_msgs::Header& header,
                                                const std::string& joint_name,
                                                trajectory_msgs::MultiDOFJointTrajectory& out);

/// An arm's JointTrajectory (joint_names in chain order; per sample positions, velocities,
/// accelerations and time_from_start); no points without an arm.
trajectory_msgs::JointTrajectory& toMsg(const TrajectoryResult& result, const std_msgs::Header& header,
                                        trajectory_msgs::JointTrajectory& out);

/// The response's figures from the result's: duration, length, rotation_length, max_linear_speed,
/// max_angular_speed, the peak accelerations and jerks, the constant-speed window, the fit's
/// residuals, energy, an arm's joint figures (success, message and the sample arrays are left as
/// they are).
GenerateTrajectory::Response& copyFigures(const TrajectoryResult& result, GenerateTrajectory::Response& out);
/// The message of a successful generation: the samples and duration, what the timing did (the
/// stretch factor of a `stretch` that slowed the curve down, the time-optimal or constant-speed
/// timing otherwise), a start state's recovery or braking, a fit's residuals. `request` is the
/// one generated, the node's defaults filled in.
std::string generationMessage(const TrajectoryRequest& request, const TrajectoryResult& result);
/// curve fit: the response's control_poses (stamped `header`) and knots from the result's; empty
/// for the other curves.
GenerateTrajectory::Response& copyFit(const TrajectoryResult& result, const std_msgs::Header& header,
                                      GenerateTrajectory::Response& out);
/// The status's figures from a response's (the same fields, "as in GenerateTrajectory.srv").
GenerationStatus& copyFigures(const GenerateTrajectory::Response& res, GenerationStatus& out);

/// rviz markers: waypoints (spheres), the control polygon, the sampled path, the blend zones
/// (a translucent sphere of radius r_i at each blended corner, ns `blend_zones`) and
/// `axes` evenly spaced body axes (x red, y green, z blue) of length `axis_length` m.
/// The first marker deletes what an earlier trajectory drew.
visualization_msgs::MarkerArray toMarkerArray(const TrajectoryResult& result,
                                              const std::vector<Pose<double>>& waypoints,
                                              const std_msgs::Header& header, int axes, double axis_length);

}  // namespace se3_interpolation
