// Parameters of se3_interpolation_node, read at start-up from the private namespace `~`;
// the request defaults and the playback settings (loop, tf_rate) change at run time through
// dynamic_reconfigure (cfg/InterpolationNode.cfg) under the same validation.
// config/se3_interpolation.yaml documents each with its unit and default.
#pragma once

#include <ros/node_handle.h>

#include <string>

#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/planner.h"

namespace se3_interpolation
{
struct NodeParameters
{
  std::string frame_id = "map";              ///< frame of waypoints whose header has none
  std::string child_frame_id = "interpolated";  ///< moving TF frame and trajectory joint name
  double tf_rate = 50.0;                     ///< Hz, moving frame broadcast rate
  bool loop = false;                         ///< replay the trajectory forever (false: hold the last pose)
  int max_tf_samples = 20;                   ///< static frames `<child_frame_id>_<k>` on /tf_static
  bool auto_generate = true;                 ///< regenerate when the waypoint buffer changes
  bool publish_tf = true;                    ///< broadcast the moving and static frames
  int marker_axes = 20;                      ///< sampled axes drawn in ~markers
  double axis_length = 0.1;                  ///< m, length of the drawn axes
  double tf_timeout = 0.1;                   ///< s, wait for a transform of a ~waypoint pose
  int waypoint_queue_size = 100;             ///< ~waypoint messages waiting to be handled (drops counted)
  int service_threads = 4;                   ///< threads serving ~generate concurrently
  double master_check_period = 1.0;          ///< s, master watchdog period (0: no watchdog)
  bool replan_from_current = true;           ///< auto-generation starts from the current motion
  double replan_lead = 0.1;                  ///< s, switch time after the request (from_current)
  PlannerLimits limits;                      ///< ~max_samples, ~max_waypoints, ~max_work_seconds
  /// Defaults for empty request fields (and the auto-generated trajectory): the core's
  /// RequestDefaults until a parameter says otherwise.
  std::string curve = toString(RequestDefaults::kCurve);
  std::string geometry = toString(RequestDefaults::kGeometry);
  std::string parameterization = toString(RequestDefaults::kParameterization);
  std::string timing = toString(RequestDefaults::kTiming);
  /// The max_* bounds of requests that leave them 0 (0 = unbounded); time_optimal needs some.
  double max_linear_velocity = 0.0;
  double max_angular_velocity = 0.0;
  double max_linear_acceleration = 0.0;
  double max_angular_acceleration = 0.0;
  double duration = 0.0;
  int sample_count = static_cast<int>(RequestDefaults::kSampleCount);
  double blend_radius = 0.0;  ///< m, for piecewise_geodesic requests without one (0: sharp corners)
};

/// Reads every parameter from `nh` (the private handle). An invalid value (out of range, an
/// unknown name such as curve "bspine", or of the wrong type) is refused with a ROS warning
/// naming the parameter, and the default is kept.
NodeParameters loadNodeParameters(const ros::NodeHandle& nh);

/// Writes every parameter of `p` to `nh` (the private handle) under the names and types
/// loadNodeParameters reads, so that reading them back gives `p`: the values in effect, e.g.
/// after a master restart lost the launch file's parameters.
void writeNodeParameters(const ros::NodeHandle& nh, const NodeParameters& p);

/// Why the string parameter `name` (without "~") cannot take `value`, naming "~<name>" and
/// quoting at most kMaxQuotedLength characters of the value; "" when it can. Covers curve,
/// geometry, parameterization, timing, frame_id and child_frame_id.
std::string stringParameterError(const std::string& name, const std::string& value);

/// Why the numeric parameter `name` cannot take `value` (its range, as in
/// config/se3_interpolation.yaml); "" when it can or when `name` has no range.
std::string numberParameterError(const std::string& name, double value);

}  // namespace se3_interpolation
