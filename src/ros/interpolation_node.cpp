#include "se3_interpolation/ros/interpolation_node.h"

#include <tf2_geometry_msgs/tf2_geometry_msgs.h>

#include <cmath>
#include <new>
#include <sstream>

#include "se3_interpolation/GenerationStatus.h"
#include "se3_interpolation/ros/conversions.h"

namespace se3_interpolation
{
namespace
{
/// tf2 frame ids: non-empty, no leading '/', no white space.
void requireFrameId(const std::string& id, const std::string& field)
{
  if (id.empty())
    throw InvalidInputError(field + ": is empty");
  if (id.front() == '/')
    throw InvalidInputError(field + ": '" + id + "' starts with '/' (tf2 frame ids have no leading slash)");
  for (char c : id)
    if (std::isspace(static_cast<unsigned char>(c)))
      throw InvalidInputError(field + ": '" + id + "' contains white space");
}
}  // namespace

InterpolationNode::InterpolationNode(ros::NodeHandle nh, ros::NodeHandle private_nh)
  : nh_(std::move(nh))
  , private_nh_(std::move(private_nh))
  , params_(loadNodeParameters(private_nh_))
  , tf_listener_(tf_buffer_)
  , buffer_frame_(params_.frame_id)
{
  path_pub_ = private_nh_.advertise<nav_msgs::Path>("path", 1, true);
  trajectory_pub_ = private_nh_.advertise<trajectory_msgs::MultiDOFJointTrajectory>("trajectory", 1, true);
  markers_pub_ = private_nh_.advertise<visualization_msgs::MarkerArray>("markers", 1, true);
  status_pub_ = private_nh_.advertise<GenerationStatus>("status", 1, true);
  generate_service_ = private_nh_.advertiseService("generate", &InterpolationNode::generate, this);
  clear_service_ = private_nh_.advertiseService("clear_waypoints", &InterpolationNode::clearWaypoints, this);
  waypoint_sub_ = private_nh_.subscribe("waypoint", 100, &InterpolationNode::waypointCallback, this);
  waypoints_sub_ = private_nh_.subscribe("waypoints", 10, &InterpolationNode::waypointsCallback, this);

  ros::NodeHandle tf_nh(private_nh_);
  tf_nh.setCallbackQueue(&tf_queue_);
  tf_timer_ = tf_nh.createTimer(ros::Duration(1.0 / params_.tf_rate), &InterpolationNode::tfTimerCallback, this);
  tf_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &tf_queue_);
  tf_spinner_->start();
}

InterpolationNode::~InterpolationNode()
{
  tf_spinner_->stop();
}

bool InterpolationNode::generate(GenerateTrajectory::Request& req, GenerateTrajectory::Response& res)
{
  generateInto(req, res);
  publishStatus(req, res, "service");
  return true;  // errors travel in res.success / res.message (a false return loses them)
}

void InterpolationNode::generateInto(const GenerateTrajectory::Request& req, GenerateTrajectory::Response& res)
{
  try
  {
    std::vector<geometry_msgs::Pose> poses;
    std::string frame;
    if (req.waypoints.poses.empty())
    {
      std::lock_guard<std::mutex> lock(buffer_mutex_);
      poses = buffer_;
      frame = buffer_frame_;
    }
    else
    {
      poses = req.waypoints.poses;
      frame = req.waypoints.header.frame_id.empty() ? params_.frame_id : req.waypoints.header.frame_id;
    }
    requireFrameId(frame, "waypoints.header.frame_id");
    const std::string child = req.child_frame_id.empty() ? params_.child_frame_id : req.child_frame_id;
    requireFrameId(child, "child_frame_id");
    if (child == frame)
      throw InvalidInputError("child_frame_id: '" + child + "' is also the waypoints' frame");

    TrajectoryRequest r = fromRequestMsg(req, poses);
    if (r.curve.empty())
      r.curve = params_.curve;
    if (r.geometry.empty())
      r.geometry = params_.geometry;
    if (r.parameterization.empty())
      r.parameterization = params_.parameterization;
    if (r.duration == 0.0)
      r.duration = params_.duration;
    if (r.sample_count == 0 && r.sample_times.empty() && r.sample_period == 0.0)
      r.sample_count = static_cast<std::uint32_t>(params_.sample_count);
    const TrajectoryResult result = generateTrajectory(r, params_.limits);

    std_msgs::Header header;
    header.frame_id = frame;
    header.stamp = req.waypoints.header.stamp.isZero() ? ros::Time::now() : req.waypoints.header.stamp;
    if (header.stamp.toSec() + result.start_time < 0.0)
      throw InvalidInputError("times: the trajectory would start before time 0 (stamp + times[0] < 0)");

    res.path = toPathMsg(result, header);
    res.trajectory = toTrajectoryMsg(result, header, child);
    res.duration = result.duration;
    res.length = result.length;
    res.rotation_length = result.rotation_length;
    res.max_linear_speed = result.max_linear_speed;
    res.max_angular_speed = result.max_angular_speed;
    res.energy = result.energy;
    res.success = true;
    std::ostringstream msg;
    msg << result.samples.size() << " samples over " << result.duration << " s";
    if (result.time_scale > 1.0)
      msg << " (time stretched x" << result.time_scale << " to meet the bounds)";
    res.message = msg.str();
    if (req.publish)
      publish(result, res, header, child);
  }
  catch (const std::bad_alloc&)
  {
    res = GenerateTrajectory::Response();
    res.success = false;
    res.message = "out of memory while generating the trajectory (reduce sample_count or the waypoints)";
  }
  catch (const std::exception& e)
  {
    res = GenerateTrajectory::Response();
    res.success = false;
    res.message = e.what();
  }
  catch (...)
  {
    res = GenerateTrajectory::Response();
    res.success = false;
    res.message = "unexpected error while generating the trajectory";
  }
}

void InterpolationNode::publish(const TrajectoryResult& result, const GenerateTrajectory::Response& res,
                                const std_msgs::Header& header, const std::string& child_frame_id)
{
  path_pub_.publish(res.path);
  trajectory_pub_.publish(res.trajectory);
  markers_pub_.publish(toMarkerArray(result, result.waypoints, header, params_.marker_axes, params_.axis_length));

  auto playback = std::make_shared<Playback>();
  playback->pose_at = result.pose_at;
  playback->stamp = header.stamp;
  playback->start_time = result.start_time;
  playback->duration = result.duration;
  playback->frame_id = header.frame_id;
  playback->child_frame_id = child_frame_id;
  {
    std::lock_guard<std::mutex> lock(playback_mutex_);
    playback_ = playback;
  }
  if (!params_.publish_tf || params_.max_tf_samples <= 0)
    return;
  std::vector<geometry_msgs::TransformStamped> frames;
  const int n = params_.max_tf_samples;
  for (int k = 0; k < n; ++k)
  {
    const double t = result.start_time + (n == 1 ? 0.0 : result.duration * k / (n - 1));
    geometry_msgs::TransformStamped ts;
    ts.header = header;
    ts.child_frame_id = child_frame_id + "_" + std::to_string(k);
    ts.transform = toTransformMsg(result.pose_at(t));
    frames.push_back(ts);
  }
  static_broadcaster_.sendTransform(frames);
}

void InterpolationNode::publishStatus(const GenerateTrajectory::Request& req, const GenerateTrajectory::Response& res,
                                      const std::string& source)
{
  GenerationStatus status;
  status.header.stamp = ros::Time::now();
  status.success = res.success;
  status.message = res.message;
  status.source = source;
  status.curve = req.curve.empty() ? params_.curve : req.curve;
  status.geometry = req.geometry.empty() ? params_.geometry : req.geometry;
  if (req.waypoints.poses.empty())
  {
    std::lock_guard<std::mutex> lock(buffer_mutex_);
    status.header.frame_id = buffer_frame_;
    status.waypoint_count = static_cast<std::uint32_t>(buffer_.size());
  }
  else
  {
    status.header.frame_id = req.waypoints.header.frame_id.empty() ? params_.frame_id : req.waypoints.header.frame_id;
    status.waypoint_count = static_cast<std::uint32_t>(req.waypoints.poses.size());
  }
  status.duration = res.duration;
  status.length = res.length;
  status.rotation_length = res.rotation_length;
  status.max_linear_speed = res.max_linear_speed;
  status.max_angular_speed = res.max_angular_speed;
  status.energy = res.energy;
  status_pub_.publish(status);
}

bool InterpolationNode::clearWaypoints(std_srvs::Trigger::Request& /*req*/, std_srvs::Trigger::Response& res)
{
  std::size_t n = 0;
  {
    std::lock_guard<std::mutex> lock(buffer_mutex_);
    n = buffer_.size();
    buffer_.clear();
  }
  res.success = true;
  res.message = "cleared " + std::to_string(n) + " waypoints";
  return true;
}

void InterpolationNode::waypointCallback(const geometry_msgs::PoseStamped::ConstPtr& msg)
{
  try
  {
    geometry_msgs::PoseStamped pose = *msg;
    std::string frame;
    {
      std::lock_guard<std::mutex> lock(buffer_mutex_);
      frame = buffer_frame_;
    }
    if (!pose.header.frame_id.empty() && pose.header.frame_id != frame)
      pose = tf_buffer_.transform(pose, frame, ros::Duration(params_.tf_timeout));
    validatePose(fromPoseMsg(pose.pose), "waypoint.pose");
    std::size_t n = 0;
    {
      std::lock_guard<std::mutex> lock(buffer_mutex_);
      if (buffer_.size() >= params_.limits.max_waypoints)
        throw LimitExceededError("the buffer holds ~max_waypoints = " + std::to_string(params_.limits.max_waypoints) +
                                 " waypoints");
      buffer_.push_back(pose.pose);
      n = buffer_.size();
    }
    ROS_DEBUG_STREAM("buffered waypoint " << n - 1);
    if (n >= 2)
      autoGenerate();
  }
  catch (const std::exception& e)
  {
    ROS_WARN_STREAM("~waypoint rejected: " << e.what());
  }
}

void InterpolationNode::waypointsCallback(const geometry_msgs::PoseArray::ConstPtr& msg)
{
  try
  {
    for (std::size_t i = 0; i < msg->poses.size(); ++i)
      validatePose(fromPoseMsg(msg->poses[i]), "waypoints.poses[" + std::to_string(i) + "]");
    if (msg->poses.size() > params_.limits.max_waypoints)
      throw LimitExceededError("more than ~max_waypoints = " + std::to_string(params_.limits.max_waypoints) +
                               " waypoints");
    const std::string frame = msg->header.frame_id.empty() ? params_.frame_id : msg->header.frame_id;
    requireFrameId(frame, "waypoints.header.frame_id");
    {
      std::lock_guard<std::mutex> lock(buffer_mutex_);
      buffer_ = msg->poses;
      buffer_frame_ = frame;
    }
    if (msg->poses.size() >= 2)
      autoGenerate();
  }
  catch (const std::exception& e)
  {
    ROS_WARN_STREAM("~waypoints rejected: " << e.what());
  }
}

void InterpolationNode::autoGenerate()
{
  if (!params_.auto_generate)
    return;
  GenerateTrajectory::Request req;
  req.publish = true;
  GenerateTrajectory::Response res;
  generateInto(req, res);
  publishStatus(req, res, "auto_generation");
  if (res.success)
    ROS_INFO_STREAM("auto-generated: " << res.message);
  else
    ROS_WARN_STREAM("auto-generation failed: " << res.message);
}

void InterpolationNode::tfTimerCallback(const ros::TimerEvent& /*event*/)
{
  std::shared_ptr<const Playback> playback;
  {
    std::lock_guard<std::mutex> lock(playback_mutex_);
    playback = playback_;
  }
  if (!playback || !params_.publish_tf)
    return;
  const ros::Time now = ros::Time::now();
  if (now <= last_tf_stamp_)
    return;  // TF stamps never repeat or go backwards
  double t = (now - playback->stamp).toSec();
  const double t0 = playback->start_time;
  const double d = playback->duration;
  if (params_.loop && d > 0.0)
  {
    double u = std::fmod(t - t0, d);
    if (u < 0.0)
      u += d;
    t = t0 + u;
  }
  else
  {
    t = std::min(std::max(t, t0), t0 + d);
  }
  geometry_msgs::TransformStamped ts;
  ts.header.stamp = now;
  ts.header.frame_id = playback->frame_id;
  ts.child_frame_id = playback->child_frame_id;
  ts.transform = toTransformMsg(playback->pose_at(t));
  tf_broadcaster_.sendTransform(ts);
  last_tf_stamp_ = now;
}

}  // namespace se3_interpolation
