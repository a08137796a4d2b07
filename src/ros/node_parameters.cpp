#include "se3_interpolation/ros/node_parameters.h"

#include <ros/console.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/validation.h"

namespace se3_interpolation
{
namespace
{
/// The range of a numeric parameter: min < x (or min <= x) and x <= max.
struct Range
{
  const char* name;
  double min;
  bool min_inclusive;
  double max;
  const char* requirement;
};

constexpr double kUnbounded = std::numeric_limits<double>::infinity();

// The ranges config/se3_interpolation.yaml states; cfg/InterpolationNode.cfg uses the same.
const Range kRanges[] = {
  { "tf_rate", 0.0, false, 1000.0, "must be in (0, 1000] Hz" },
  { "max_tf_samples", 0.0, true, 1000.0, "must be in 0 ... 1000" },
  { "marker_axes", 0.0, true, 1000.0, "must be in 0 ... 1000" },
  { "axis_length", 0.0, false, kUnbounded, "must be > 0 m" },
  { "tf_timeout", 0.0, true, kUnbounded, "must be >= 0 s" },
  { "waypoint_queue_size", 1.0, true, 100000.0, "must be in 1 ... 100000" },
  { "service_threads", 1.0, true, 64.0, "must be in 1 ... 64" },
  { "master_check_period", 0.0, true, kUnbounded, "must be >= 0 s" },
  // A switch further ahead than 10 s would leave the new request waiting on the old motion for
  // longer than any replanning needs (a generation takes well under a second, docs/performance.md).
  { "replan_lead", 0.0, true, 10.0, "must be in [0, 10] s" },
  { "max_samples", 2.0, true, kUnbounded, "must be >= 2" },
  { "max_waypoints", 2.0, true, kUnbounded, "must be >= 2" },
  { "max_work_seconds", 0.0, false, kUnbounded, "must be > 0 s" },
  { "max_linear_velocity", 0.0, true, kUnbounded, "must be >= 0 m/s (0: unbounded)" },
  { "max_angular_velocity", 0.0, true, kUnbounded, "must be >= 0 rad/s (0: unbounded)" },
  { "max_linear_acceleration", 0.0, true, kUnbounded, "must be >= 0 m/s^2 (0: unbounded)" },
  { "max_angular_acceleration", 0.0, true, kUnbounded, "must be >= 0 rad/s^2 (0: unbounded)" },
  { "duration", 0.0, true, kUnbounded, "must be >= 0 s" },
  { "sample_count", 2.0, true, kUnbounded, "must be >= 2" },
  { "blend_radius", 0.0, true, kUnbounded, "must be >= 0 m" },
};

std::string show(const std::string& value)
{
  return quotedText(value);
}
template <class T>
T show(const T& value)
{
  return value;
}

/// Reads `name` into `value` if it is set, of type T and `error` finds nothing wrong with it;
/// else warns naming the parameter and keeps `value`.
template <class T, class Check>
void read(const ros::NodeHandle& nh, const std::string& name, T* value, Check error)
{
  if (!nh.hasParam(name))
    return;
  T candidate;
  if (!nh.getParam(name, candidate))
  {
    ROS_WARN_STREAM("~" << name << ": refused (not of the expected type); keeping " << show(*value));
    return;
  }
  const std::string why = error(candidate);
  if (!why.empty())
  {
    ROS_WARN_STREAM(why << "; keeping " << show(*value));
    return;
  }
  *value = candidate;
}

void readString(const ros::NodeHandle& nh, const std::string& name, std::string* value)
{
  read<std::string>(nh, name, value, [&](const std::string& s) { return stringParameterError(name, s); });
}

template <class T>
void readNumber(const ros::NodeHandle& nh, const std::string& name, T* value)
{
  read<T>(nh, name, value, [&](const T& x) { return numberParameterError(name, static_cast<double>(x)); });
}

void readBool(const ros::NodeHandle& nh, const std::string& name, bool* value)
{
  read<bool>(nh, name, value, [](const bool&) { return std::string(); });
}

/// An unsigned limit read through an int parameter.
void readLimit(const ros::NodeHandle& nh, const std::string& name, std::size_t* value)
{
  int candidate = static_cast<int>(*value);
  readNumber(nh, name, &candidate);
  *value = static_cast<std::size_t>(candidate);
}
}  // namespace

std::string stringParameterError(const std::string& name, const std::string& value)
{
  const std::string field = "~" + name;
  try
  {
    if (name == "frame_id" || name == "child_frame_id")
      validateFrameId(value, field);
    else if (value.empty())
      return field + ": refused (empty; expected a name)";
    else if (value.size() > kMaxFrameIdLength)
      return field + ": refused (" + show(value) + " is no known name)";
    else if (name == "curve")
      parseName(value, field, RequestDefaults::kCurve);
    else if (name == "geometry")
      parseName(value, field, RequestDefaults::kGeometry);
    else if (name == "parameterization")
      parseName(value, field, RequestDefaults::kParameterization);
    else if (name == "timing")
      parseName(value, field, RequestDefaults::kTiming);
  }
  catch (const InvalidInputError& e)
  {
    return e.what();
  }
  return "";
}

std::string numberParameterError(const std::string& name, double value)
{
  for (const Range& r : kRanges)
  {
    if (name != r.name)
      continue;
    const bool above_min = r.min_inclusive ? value >= r.min : value > r.min;
    if (std::isfinite(value) && above_min && value <= r.max)
      return "";
    std::ostringstream why;
    why << "~" << name << ": refused " << value << " (" << r.requirement << ")";
    return why.str();
  }
  return "";
}

NodeParameters loadNodeParameters(const ros::NodeHandle& nh)
{
  NodeParameters p;
  readString(nh, "frame_id", &p.frame_id);
  readString(nh, "child_frame_id", &p.child_frame_id);
  readNumber(nh, "tf_rate", &p.tf_rate);
  readBool(nh, "loop", &p.loop);
  readNumber(nh, "max_tf_samples", &p.max_tf_samples);
  readBool(nh, "auto_generate", &p.auto_generate);
  readBool(nh, "publish_tf", &p.publish_tf);
  readNumber(nh, "marker_axes", &p.marker_axes);
  readNumber(nh, "axis_length", &p.axis_length);
  readNumber(nh, "tf_timeout", &p.tf_timeout);
  readNumber(nh, "waypoint_queue_size", &p.waypoint_queue_size);
  readNumber(nh, "service_threads", &p.service_threads);
  readNumber(nh, "master_check_period", &p.master_check_period);
  readBool(nh, "replan_from_current", &p.replan_from_current);
  readNumber(nh, "replan_lead", &p.replan_lead);
  readLimit(nh, "max_samples", &p.limits.max_samples);
  readLimit(nh, "max_waypoints", &p.limits.max_waypoints);
  readNumber(nh, "max_work_seconds", &p.limits.max_work_seconds);
  readString(nh, "curve", &p.curve);
  readString(nh, "geometry", &p.geometry);
  readString(nh, "parameterization", &p.parameterization);
  readString(nh, "timing", &p.timing);
  readNumber(nh, "max_linear_velocity", &p.max_linear_velocity);
  readNumber(nh, "max_angular_velocity", &p.max_angular_velocity);
  readNumber(nh, "max_linear_acceleration", &p.max_linear_acceleration);
  readNumber(nh, "max_angular_acceleration", &p.max_angular_acceleration);
  readNumber(nh, "duration", &p.duration);
  readNumber(nh, "sample_count", &p.sample_count);
  readNumber(nh, "blend_radius", &p.blend_radius);
  return p;
}

void writeNodeParameters(const ros::NodeHandle& nh, const NodeParameters& p)
{
  nh.setParam("frame_id", p.frame_id);
  nh.setParam("child_frame_id", p.child_frame_id);
  nh.setParam("tf_rate", p.tf_rate);
  nh.setParam("loop", p.loop);
  nh.setParam("max_tf_samples", p.max_tf_samples);
  nh.setParam("auto_generate", p.auto_generate);
  nh.setParam("publish_tf", p.publish_tf);
  nh.setParam("marker_axes", p.marker_axes);
  nh.setParam("axis_length", p.axis_length);
  nh.setParam("tf_timeout", p.tf_timeout);
  nh.setParam("waypoint_queue_size", p.waypoint_queue_size);
  nh.setParam("service_threads", p.service_threads);
  nh.setParam("master_check_period", p.master_check_period);
  nh.setParam("replan_from_current", p.replan_from_current);
  nh.setParam("replan_lead", p.replan_lead);
  nh.setParam("max_samples", static_cast<int>(p.limits.max_samples));
  nh.setParam("max_waypoints", static_cast<int>(p.limits.max_waypoints));
  nh.setParam("max_work_seconds", p.limits.max_work_seconds);
  nh.setParam("curve", p.curve);
  nh.setParam("geometry", p.geometry);
  nh.setParam("parameterization", p.parameterization);
  nh.setParam("timing", p.timing);
  nh.setParam("max_linear_velocity", p.max_linear_velocity);
  nh.setParam("max_angular_velocity", p.max_angular_velocity);
  nh.setParam("max_linear_acceleration", p.max_linear_acceleration);
  nh.setParam("max_angular_acceleration", p.max_angular_acceleration);
  nh.setParam("duration", p.duration);
  nh.setParam("sample_count", p.sample_count);
  nh.setParam("blend_radius", p.blend_radius);
}

}  // namespace se3_interpolation
