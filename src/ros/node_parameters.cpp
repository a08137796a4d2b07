#include "se3_interpolation/ros/node_parameters.h"

#include <ros/console.h>

#include <cmath>
#include <functional>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/validation.h"

namespace se3_interpolation
{
namespace
{
template <class T>
void read(const ros::NodeHandle& nh, const std::string& name, T* value, const std::function<bool(const T&)>& valid,
          const char* requirement)
{
  T candidate;
  if (!nh.getParam(name, candidate))
    return;
  if (!valid(candidate))
  {
    ROS_WARN_STREAM("~" << name << ": refused (" << requirement << "); keeping " << *value);
    return;
  }
  *value = candidate;
}
}  // namespace

NodeParameters loadNodeParameters(const ros::NodeHandle& nh)
{
  NodeParameters p;
  auto non_empty = [](const std::string& s) { return !s.empty(); };
  auto positive = [](const double& x) { return std::isfinite(x) && x > 0.0; };
  auto non_negative = [](const double& x) { return std::isfinite(x) && x >= 0.0; };
  auto any = [](const bool&) { return true; };
  auto frame_id = [](const std::string& s) {
    try
    {
      validateFrameId(s, "frame id");
      return true;
    }
    catch (const InvalidInputError&)
    {
      return false;
    }
  };
  read<std::string>(nh, "frame_id", &p.frame_id, frame_id, "a tf2 frame id of at most 256 printable characters");
  read<std::string>(nh, "child_frame_id", &p.child_frame_id, frame_id,
                    "a tf2 frame id of at most 256 printable characters");
  read<double>(nh, "tf_rate", &p.tf_rate, [](const double& x) { return std::isfinite(x) && x > 0.0 && x <= 1000.0; },
               "must be in (0, 1000] Hz");
  read<bool>(nh, "loop", &p.loop, any, "");
  read<int>(nh, "max_tf_samples", &p.max_tf_samples, [](const int& x) { return x >= 0 && x <= 1000; },
            "must be in 0 ... 1000");
  read<bool>(nh, "auto_generate", &p.auto_generate, any, "");
  read<bool>(nh, "publish_tf", &p.publish_tf, any, "");
  read<int>(nh, "marker_axes", &p.marker_axes, [](const int& x) { return x >= 0 && x <= 1000; }, "must be in 0 ... 1000");
  read<double>(nh, "axis_length", &p.axis_length, positive, "must be > 0 m");
  read<double>(nh, "tf_timeout", &p.tf_timeout, non_negative, "must be >= 0 s");
  read<int>(nh, "waypoint_queue_size", &p.waypoint_queue_size, [](const int& x) { return x >= 1 && x <= 100000; },
            "must be in 1 ... 100000");
  read<int>(nh, "service_threads", &p.service_threads, [](const int& x) { return x >= 1 && x <= 64; },
            "must be in 1 ... 64");
  read<double>(nh, "master_check_period", &p.master_check_period, non_negative, "must be >= 0 s");
  int max_samples = static_cast<int>(p.limits.max_samples);
  read<int>(nh, "max_samples", &max_samples, [](const int& x) { return x >= 2; }, "must be >= 2");
  p.limits.max_samples = static_cast<std::size_t>(max_samples);
  int max_waypoints = static_cast<int>(p.limits.max_waypoints);
  read<int>(nh, "max_waypoints", &max_waypoints, [](const int& x) { return x >= 2; }, "must be >= 2");
  p.limits.max_waypoints = static_cast<std::size_t>(max_waypoints);
  read<double>(nh, "max_work", &p.limits.max_work, positive, "must be > 0 work units");
  read<std::string>(nh, "curve", &p.curve, non_empty, "must not be empty");
  read<std::string>(nh, "geometry", &p.geometry, non_empty, "must not be empty");
  read<std::string>(nh, "parameterization", &p.parameterization, non_empty, "must not be empty");
  read<std::string>(nh, "timing", &p.timing, [](const std::string& x) { return x == "stretch" || x == "time_optimal"; },
                    "must be stretch or time_optimal");
  read<double>(nh, "max_linear_velocity", &p.max_linear_velocity, non_negative, "must be >= 0 m/s (0: unbounded)");
  read<double>(nh, "max_angular_velocity", &p.max_angular_velocity, non_negative, "must be >= 0 rad/s (0: unbounded)");
  read<double>(nh, "max_linear_acceleration", &p.max_linear_acceleration, non_negative,
               "must be >= 0 m/s^2 (0: unbounded)");
  read<double>(nh, "max_angular_acceleration", &p.max_angular_acceleration, non_negative,
               "must be >= 0 rad/s^2 (0: unbounded)");
  read<double>(nh, "duration", &p.duration, non_negative, "must be >= 0 s");
  read<int>(nh, "sample_count", &p.sample_count, [](const int& x) { return x >= 2; }, "must be >= 2");
  read<double>(nh, "blend_radius", &p.blend_radius, non_negative, "must be >= 0 m");
  return p;
}

}  // namespace se3_interpolation
