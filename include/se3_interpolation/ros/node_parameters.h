// Parameters of se3_interpolation_node, read once from the private namespace `~`.
// config/se3_interpolation.yaml documents each with its unit and default.
#pragma once

#include <ros/node_handle.h>

#include <string>

#include "se3_interpolation/planner.h"

namespace se3_interpolation
{
struct NodeParameters
{
  std::string frame_id = "map";              ///< frame of waypoints whose header has none
  std::string child_frame_id = "interpolated";  ///< moving TF frame and trajectory joint name
  double tf_rate = 50.0;                     ///< Hz, moving frame broadcast rate
  bool loop = true;                          ///< replay the trajectory on the moving frame
  int max_tf_samples = 20;                   ///< static frames <child_frame_id>_<k> on /tf_static
  bool auto_generate = true;                 ///< regenerate when the waypoint buffer changes
  bool publish_tf = true;                    ///< broadcast the moving and static frames
  int marker_axes = 20;                      ///< sampled axes drawn in ~markers
  double axis_length = 0.1;                  ///< m, length of the drawn axes
  double tf_timeout = 0.1;                   ///< s, wait for a transform of a ~waypoint pose
  PlannerLimits limits;                      ///< ~max_samples, ~max_waypoints
  /// Defaults for empty request fields (and the auto-generated trajectory).
  std::string curve = "interpolating";
  std::string geometry = "double_geodesic";
  std::string parameterization = "chord";
  double duration = 0.0;
  int sample_count = 100;
};

/// Reads every parameter from `nh` (the private handle). An invalid value is refused
/// with a ROS warning naming it and the default is kept.
NodeParameters loadNodeParameters(const ros::NodeHandle& nh);

}  // namespace se3_interpolation
