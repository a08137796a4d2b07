#include "se3_interpolation/ros/conversions.h"

#include <tf2_eigen/tf2_eigen.h>

#include <sstream>

#include "se3_interpolation/planner/names.h"

namespace se3_interpolation
{
namespace
{
/// The quaternion kept as given (its sign too; not normalised here).
Pose<double> poseOf(const geometry_msgs::Quaternion& orientation, const Eigen::Vector3d& position)
{
  Eigen::Quaterniond q;
  tf2::fromMsg(orientation, q);
  return Pose<double>(q, position);
}
}  // namespace

Pose<double> fromMsg(const geometry_msgs::Pose& msg)
{
  Eigen::Vector3d p;
  tf2::fromMsg(msg.position, p);
  return poseOf(msg.orientation, p);
}

geometry_msgs::Pose toMsg(const Pose<double>& pose)
{
  geometry_msgs::Pose msg;
  msg.position = tf2::toMsg(Eigen::Vector3d(pose.p));
  msg.orientation = tf2::toMsg(Eigen::Quaterniond(pose.q));
  return msg;
}

Twist fromMsg(const geometry_msgs::Twist& msg)
{
  Eigen::Matrix<double, 6, 1> v;
  tf2::fromMsg(msg, v);  // (linear, angular)
  Twist t;
  t.linear = v.head<3>();
  t.angular = v.tail<3>();
  return t;
}

geometry_msgs::Twist toMsg(const Twist& twist)
{
  Eigen::Matrix<double, 6, 1> v;
  v << twist.linear, twist.angular;
  return tf2::toMsg(v);
}

geometry_msgs::Transform& toMsg(const Pose<double>& pose, geometry_msgs::Transform& out)
{
  tf2::toMsg(Eigen::Vector3d(pose.p), out.translation);
  out.rotation = tf2::toMsg(Eigen::Quaterniond(pose.q));
  return out;
}

Pose<double> fromMsg(const geometry_msgs::Transform& msg)
{
  Eigen::Vector3d p;
  tf2::fromMsg(msg.translation, p);
  return poseOf(msg.rotation, p);
}

GoalPoint fromMsg(const trajectory_msgs::MultiDOFJointTrajectoryPoint& msg)
{
  GoalPoint point;
  point.time_from_start = msg.time_from_start.toSec();
  if (!msg.transforms.empty())
    point.pose = fromMsg(msg.transforms.front());
  if (!msg.velocities.empty())
    point.velocity = fromMsg(msg.velocities.front());
  if (!msg.accelerations.empty())
    point.acceleration = fromMsg(msg.accelerations.front());
  return point;
}

TrajectoryRequest fromMsg(const GenerateTrajectory::Request& msg, const std::vector<geometry_msgs::Pose>& poses)
{
  TrajectoryRequest r;
  r.waypoints.reserve(poses.size());
  for (const auto& p : poses)
    r.waypoints.push_back(fromMsg(p));
  r.times = msg.times;
  r.curve = msg.curve;
  r.geometry = msg.geometry;
  r.degree = msg.degree;
  r.knots = msg.knots;
  r.continuity = msg.continuity;
  r.blend_radius = msg.blend_radius;
  r.end_condition = msg.end_condition;
  r.start_velocity = fromMsg(msg.start_velocity);
  r.end_velocity = fromMsg(msg.end_velocity);
  r.start_acceleration = fromMsg(msg.start_acceleration);
  for (const auto& v : msg.velocities)
    r.velocities.push_back(fromMsg(v));
  r.parameterization = msg.parameterization;
  r.rotation_scale = msg.rotation_scale;
  r.duration = msg.duration;
  r.max_linear_velocity = msg.max_linear_velocity;
  r.max_angular_velocity = msg.max_angular_velocity;
  r.max_linear_acceleration = msg.max_linear_acceleration;
  r.max_angular_acceleration = msg.max_angular_acceleration;
  r.max_linear_jerk = msg.max_linear_jerk;
  r.max_angular_jerk = msg.max_angular_jerk;
  r.timing = msg.timing;
  r.speed = msg.speed;
  r.control_period = msg.control_period;
  r.smoothing = msg.smoothing;
  r.loss = msg.loss;
  r.loss_scale = msg.loss_scale;
  r.sample_times = msg.sample_times;
  r.sample_period = msg.sample_period;
  r.sample_count = msg.sample_count;
  r.sample_tolerance = msg.sample_tolerance;
  r.joint_seed = msg.joint_seed;
  return r;
}

nav_msgs::Path& toMsg(const TrajectoryResult& result, const std_msgs::Header& header, nav_msgs::Path& path)
{
  path.header = header;
  path.poses.resize(result.samples.size());
  for (std::size_t i = 0; i < result.samples.size(); ++i)
  {
    path.poses[i].header.frame_id = header.frame_id;
    path.poses[i].header.stamp = header.stamp + ros::Duration(result.samples[i].time);
    path.poses[i].pose = toMsg(result.samples[i].pose);
  }
  return path;
}

trajectory_msgs::MultiDOFJointTrajectory& toMsg(const TrajectoryResult& result, const std_msgs::Header& header,
                                                const std::string& joint_name,
                                                trajectory_msgs::MultiDOFJointTrajectory& traj)
{
  traj.header = header;
  traj.joint_names.assign(1, joint_name);
  traj.points.resize(result.samples.size());
  for (std::size_t i = 0; i < result.samples.size(); ++i)
  {
    const TrajectorySample& s = result.samples[i];
    auto& point = traj.points[i];
    point.transforms.resize(1);
    toMsg(s.pose, point.transforms[0]);
    point.velocities.assign(1, toMsg(s.velocity));
    point.accelerations.assign(1, toMsg(s.acceleration));
    point.time_from_start = ros::Duration(s.time);
  }
  return traj;
}

trajectory_msgs::JointTrajectory& toMsg(const TrajectoryResult& result, const std_msgs::Header& header,
                                        trajectory_msgs::JointTrajectory& traj)
{
  traj.header = header;
  traj.joint_names = result.joint_names;
  traj.points.resize(result.joint_names.empty() ? 0 : result.samples.size());
  const auto copy = [](const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
  for (std::size_t i = 0; i < traj.points.size(); ++i)
  {
    const TrajectorySample& s = result.samples[i];
    auto& point = traj.points[i];
    point.positions = copy(s.joint_position);
    point.velocities = copy(s.joint_velocity);
    point.accelerations = copy(s.joint_acceleration);
    point.time_from_start = ros::Duration(s.time);
  }
  return traj;
}

GenerateTrajectory::Response& copyFigures(const TrajectoryResult& result, GenerateTrajectory::Response& out)
{
  out.duration = result.duration;
  out.length = result.figures.length;
  out.rotation_length = result.figures.rotation_length;
  out.max_linear_speed = result.figures.max_linear_speed;
  out.max_angular_speed = result.figures.max_angular_speed;
  out.peak_linear_acceleration = result.figures.max_linear_acceleration;
  out.peak_angular_acceleration = result.figures.max_angular_acceleration;
  out.peak_linear_jerk = result.figures.max_linear_jerk;
  out.peak_angular_jerk = result.figures.max_angular_jerk;
  out.constant_speed_start = result.constant_speed_start;
  out.constant_speed_end = result.constant_speed_end;
  out.residual_linear = result.residual_linear;
  out.residual_angular = result.residual_angular;
  out.energy = result.figures.energy;
  out.joint_max_velocity.clear();
  out.joint_max_acceleration.clear();
  out.joint_max_jerk.clear();
  for (const arm::JointPeak& p : result.joint_figures.peaks)
  {
    out.joint_max_velocity.push_back(p.velocity);
    out.joint_max_acceleration.push_back(p.acceleration);
    if (result.joint_figures.has_jerk)
      out.joint_max_jerk.push_back(p.jerk);
  }
  const int binding = result.joint_figures.binding_joint;
  out.joint_binding =
      binding < 0 || result.joint_names.empty() ?
          std::string() :
          result.joint_names[static_cast<std::size_t>(binding)] + " " + result.joint_figures.binding_quantity;
  out.joint_binding_ratio = binding < 0 ? 0.0 : result.joint_figures.binding_ratio;
  return out;
}

std::string generationMessage(const TrajectoryRequest& request, const TrajectoryResult& result)
{
  std::ostringstream msg;
  msg << result.samples.size() << " samples over " << result.duration << " s";
  switch (parseName(request.timing, "timing", RequestDefaults::kTiming))
  {
    case Timing::kStretch:
      if (result.time_scale > 1.0)
        msg << " (time stretched x" << result.time_scale << " to meet the bounds)";
      break;
    case Timing::kTimeOptimal:
      msg << " (time-optimal within the bounds"
          << (request.max_linear_jerk > 0.0 || request.max_angular_jerk > 0.0 ? ", jerk-limited" : "") << ")";
      break;
    case Timing::kConstantSpeed:
      msg << " (constant speed " << request.speed << " m/s from t = " << result.constant_speed_start << " to "
          << result.constant_speed_end << " s)";
      break;
  }
  if (result.recovery_time > 0.0)
    msg << "; the start state exceeds a bound: every bound holds from t = " << result.recovery_time
        << " s on (recovery_time)";
  if (result.stop_time > 0.0)
    msg << "; the start state cannot continue along the curve within the bounds: it brakes to rest along "
           "its own directions in the first "
        << result.stop_time << " s, and the motion from rest follows";
  if (!result.knots.empty())
    msg << "; fitted " << result.control_points.size() << " control poses to " << result.waypoints.size()
        << " waypoints (residual_linear " << result.residual_linear << " m, residual_angular "
        << result.residual_angular << " rad)";
  return msg.str();
}

GenerateTrajectory::Response& copyFit(const TrajectoryResult& result, const std_msgs::Header& header,
                                      GenerateTrajectory::Response& out)
{
  out.knots = result.knots;
  out.control_poses.poses.clear();
  if (result.knots.empty())
    return out;
  out.control_poses.header = header;
  out.control_poses.poses.reserve(result.control_points.size());
  for (const Pose<double>& x : result.control_points)
    out.control_poses.poses.push_back(toMsg(x));
  return out;
}

GenerationStatus& copyFigures(const GenerateTrajectory::Response& res, GenerationStatus& out)
{
  out.duration = res.duration;
  out.length = res.length;
  out.rotation_length = res.rotation_length;
  out.max_linear_speed = res.max_linear_speed;
  out.max_angular_speed = res.max_angular_speed;
  out.peak_linear_acceleration = res.peak_linear_acceleration;
  out.peak_angular_acceleration = res.peak_angular_acceleration;
  out.peak_linear_jerk = res.peak_linear_jerk;
  out.peak_angular_jerk = res.peak_angular_jerk;
  out.constant_speed_start = res.constant_speed_start;
  out.constant_speed_end = res.constant_speed_end;
  out.residual_linear = res.residual_linear;
  out.residual_angular = res.residual_angular;
  out.energy = res.energy;
  out.joint_binding = res.joint_binding;
  out.joint_binding_ratio = res.joint_binding_ratio;
  return out;
}

}  // namespace se3_interpolation

namespace se3_interpolation
{
namespace
{
std_msgs::ColorRGBA color(float r, float g, float b, float a = 1.0F)
{
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

visualization_msgs::Marker marker(const std_msgs::Header& header, const std::string& ns, int type, double scale,
                                  const std_msgs::ColorRGBA& c)
{
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = ns;
  m.id = 0;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = scale;
  m.scale.y = scale;
  m.scale.z = scale;
  m.color = c;
  return m;
}
}  // namespace

visualization_msgs::MarkerArray toMarkerArray(const TrajectoryResult& result,
                                              const std::vector<Pose<double>>& waypoints,
                                              const std_msgs::Header& header, int axes, double axis_length)
{
  visualization_msgs::MarkerArray array;
  visualization_msgs::Marker clear;
  clear.header = header;
  clear.action = visualization_msgs::Marker::DELETEALL;
  array.markers.push_back(clear);

  auto points = marker(header, "waypoints", visualization_msgs::Marker::SPHERE_LIST, 0.05, color(1.0F, 0.8F, 0.1F));
  for (const auto& w : waypoints)
    points.points.push_back(tf2::toMsg(Eigen::Vector3d(w.p)));
  array.markers.push_back(points);

  auto polygon =
      marker(header, "control_polygon", visualization_msgs::Marker::LINE_STRIP, 0.005, color(0.6F, 0.6F, 0.6F, 0.8F));
  for (const auto& c : result.control_points)
    polygon.points.push_back(tf2::toMsg(Eigen::Vector3d(c.p)));
  array.markers.push_back(polygon);

  auto path = marker(header, "path", visualization_msgs::Marker::LINE_STRIP, 0.01, color(0.1F, 0.6F, 1.0F));
  for (const auto& s : result.samples)
    path.points.push_back(tf2::toMsg(Eigen::Vector3d(s.pose.p)));
  array.markers.push_back(path);

  // Blend zones: the chord-distance ball of radius r_i projects onto positions as the sphere
  // of radius r_i about the corner (|dp| <= r_i); the blended path stays inside it.
  for (std::size_t i = 0; i < result.blend_radii.size() && i < result.waypoints.size(); ++i)
  {
    if (!(result.blend_radii[i] > 0.0))
      continue;
    auto zone = marker(header, "blend_zones", visualization_msgs::Marker::SPHERE, 2.0 * result.blend_radii[i],
                       color(0.2F, 0.9F, 0.4F, 0.25F));
    zone.id = static_cast<int>(i);
    zone.pose.position = tf2::toMsg(Eigen::Vector3d(result.waypoints[i].p));
    array.markers.push_back(zone);
  }

  if (axes > 0 && !result.samples.empty())
  {
    auto lines = marker(header, "axes", visualization_msgs::Marker::LINE_LIST, 0.008, color(1.0F, 1.0F, 1.0F));
    const std_msgs::ColorRGBA rgb[] = { color(1.0F, 0.0F, 0.0F), color(0.0F, 1.0F, 0.0F), color(0.0F, 0.0F, 1.0F) };
    const std::size_t n = result.samples.size();
    const std::size_t count = std::min<std::size_t>(static_cast<std::size_t>(axes), n);
    for (std::size_t k = 0; k < count; ++k)
    {
      const std::size_t i = count == 1 ? 0 : k * (n - 1) / (count - 1);
      const Pose<double>& pose = result.samples[i].pose;
      const Eigen::Matrix3d r = pose.q.toRotationMatrix();
      for (int axis = 0; axis < 3; ++axis)
      {
        lines.points.push_back(tf2::toMsg(Eigen::Vector3d(pose.p)));
        lines.points.push_back(tf2::toMsg(Eigen::Vector3d(pose.p + axis_length * r.col(axis))));
        lines.colors.push_back(rgb[axis]);
        lines.colors.push_back(rgb[axis]);
      }
    }
    array.markers.push_back(lines);
  }
  return array;
}

}  // namespace se3_interpolation
