// geometry/trajectory_sample.h: a pose motion's state at a time, the form in which every layer
// above hands motions on (the planner's samples, the goals the execution follows and checks, the
// setpoint it plays), and the choice of geometry that interpolates between such states.
#pragma once

#include "se3_interpolation/geometry/pose.h"

namespace se3_interpolation
{
/// The geometry of a request's curves and of a goal's interpolation between its points
/// (geometry/geometry.h): the double geodesic or the screw motion of SE(3).
enum class GeometryType
{
  kDoubleGeodesic,
  kScrew
};

/// A pose motion's state at `time`: world_T_body and its spatial velocity and acceleration
/// (twists (linear, angular): m/s, rad/s and m/s², rad/s²).
struct TrajectorySample
{
  double time = 0.0;  ///< s after the request stamp
  Pose<double> pose;  ///< world_T_body, quaternion sign-continuous along the samples
  Twist velocity;
  Twist acceleration;
  /// With an arm following the motion (arm/joint_path.h): its movable joints' positions (rad, m),
  /// velocities and accelerations in chain order; empty without one.
  Eigen::VectorXd joint_position;
  Eigen::VectorXd joint_velocity;
  Eigen::VectorXd joint_acceleration;
};
}  // namespace se3_interpolation
