#include "se3_interpolation/ros/interpolation_node.h"

#include <ros/master.h>
#include <ros/this_node.h>
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <cstdint>
#include <new>
#include <sstream>

#include "se3_interpolation/GenerationStatus.h"
#include "se3_interpolation/ros/conversions.h"
#include "se3_interpolation/planner/validation.h"

namespace se3_interpolation
{
namespace
{
/// Longest error text the node logs or returns: exceptions from tf2 or roscpp may quote
/// strings of any length.
constexpr std::size_t kMaxMessageLength = 1024;

std::string bounded(const char* what)
{
  const std::string m(what);
  return m.size() <= kMaxMessageLength ? m : m.substr(0, kMaxMessageLength) + "... (truncated)";
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
  tf_static_pub_ = nh_.advertise<tf2_msgs::TFMessage>("/tf_static", 1, true);
  status_pub_ = private_nh_.advertise<GenerationStatus>("status", 1, true);
  clear_service_ = private_nh_.advertiseService("clear_waypoints", &InterpolationNode::clearWaypoints, this);
  waypoints_sub_ = private_nh_.subscribe("waypoints", 10, &InterpolationNode::waypointsCallback, this);

  ros::NodeHandle service_nh(private_nh_);
  service_nh.setCallbackQueue(&service_queue_);
  generate_service_ = service_nh.advertiseService("generate", &InterpolationNode::generate, this);
  service_spinner_ = std::make_unique<ros::AsyncSpinner>(params_.service_threads, &service_queue_);
  service_spinner_->start();

  ros::NodeHandle waypoint_nh(private_nh_);
  waypoint_nh.setCallbackQueue(&waypoint_queue_);
  waypoint_sub_ = waypoint_nh.subscribe("waypoint", static_cast<std::uint32_t>(params_.waypoint_queue_size),
                                        &InterpolationNode::waypointCallback, this);
  waypoint_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &waypoint_queue_);
  waypoint_spinner_->start();

  ros::NodeHandle tf_nh(private_nh_);
  tf_nh.setCallbackQueue(&tf_queue_);
  tf_timer_ = tf_nh.createTimer(ros::Duration(1.0 / params_.tf_rate), &InterpolationNode::tfTimerCallback, this);
  tf_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &tf_queue_);
  tf_spinner_->start();

  if (params_.master_check_period > 0.0)
  {
    ros::NodeHandle watchdog_nh(private_nh_);
    watchdog_nh.setCallbackQueue(&watchdog_queue_);
    watchdog_timer_ = watchdog_nh.createTimer(ros::Duration(params_.master_check_period),
                                              &InterpolationNode::watchdogCallback, this);
    watchdog_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &watchdog_queue_);
    watchdog_spinner_->start();
  }
  ROS_INFO_STREAM("se3_interpolation_node ready: services " << generate_service_.getService() << ", "
                  << clear_service_.getService() << "; waypoints on " << waypoint_sub_.getTopic() << ", "
                  << waypoints_sub_.getTopic() << "; frames " << params_.frame_id << " -> " << params_.child_frame_id
                  << (params_.publish_tf ? "" : " (TF off)") << " at " << params_.tf_rate << " Hz"
                  << (params_.loop ? " looping" : "") << ", " << params_.max_tf_samples << " static; defaults curve "
                  << params_.curve << ", geometry " << params_.geometry << ", parameterization "
                  << params_.parameterization << "; auto_generate " << (params_.auto_generate ? "on" : "off")
                  << "; max_samples " << params_.limits.max_samples << ", max_waypoints "
                  << params_.limits.max_waypoints);
}

InterpolationNode::~InterpolationNode()
{
  if (watchdog_spinner_)
    watchdog_spinner_->stop();
  tf_spinner_->stop();
  waypoint_spinner_->stop();
  service_spinner_->stop();
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
      if (poses.size() < 2)
        throw InvalidInputError("waypoints: 0 given and the ~waypoint buffer " +
                                (poses.empty() ? std::string("is empty") : "holds only 1") +
                                "; at least 2 are needed");
    }
    else
    {
      poses = req.waypoints.poses;
      frame = req.waypoints.header.frame_id.empty() ? params_.frame_id : req.waypoints.header.frame_id;
    }
    validateFrameId(frame, "waypoints.header.frame_id");
    const std::string child = req.child_frame_id.empty() ? params_.child_frame_id : req.child_frame_id;
    validateFrameId(child, "child_frame_id");
    if (child == frame)
      throw InvalidInputError("child_frame_id: " + quoted(child) + " is also the waypoints' frame");

    TrajectoryRequest r = fromRequestMsg(req, poses);
    if (r.curve.empty())
      r.curve = params_.curve;
    // The node's default radius applies to the curve that uses it only (never an error elsewhere).
    if (r.blend_radius == 0.0 && r.curve == "piecewise_geodesic")
      r.blend_radius = params_.blend_radius;
    if (r.geometry.empty())
      r.geometry = params_.geometry;
    if (r.parameterization.empty())
      r.parameterization = params_.parameterization;
    if (r.timing.empty())
      r.timing = params_.timing;
    for (auto bound : { std::make_pair(&r.max_linear_velocity, params_.max_linear_velocity),
                        std::make_pair(&r.max_angular_velocity, params_.max_angular_velocity),
                        std::make_pair(&r.max_linear_acceleration, params_.max_linear_acceleration),
                        std::make_pair(&r.max_angular_acceleration, params_.max_angular_acceleration) })
      if (*bound.first == 0.0)
        *bound.first = bound.second;
    if (r.duration == 0.0)
      r.duration = params_.duration;
    if (r.sample_count == 0 && r.sample_times.empty() && r.sample_period == 0.0)
      r.sample_count = static_cast<std::uint32_t>(params_.sample_count);
    const TrajectoryResult result = generateTrajectory(r, params_.limits);

    std_msgs::Header header;
    header.frame_id = frame;
    header.stamp = req.waypoints.header.stamp.isZero() ? ros::Time::now() : req.waypoints.header.stamp;
    validateStampedSpan(header.stamp.toSec(), result.start_time, result.start_time + result.duration,
                        "waypoints.header.stamp");

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
    res.message = bounded(e.what());
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
  std::lock_guard<std::mutex> publishing(publish_mutex_);
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
  // The whole set, replacing the latched one: /tf_static holds this trajectory's frames only.
  tf2_msgs::TFMessage frames;
  const int n = params_.max_tf_samples;
  for (int k = 0; k < n; ++k)
  {
    const double t = result.start_time + (n == 1 ? 0.0 : result.duration * k / (n - 1));
    geometry_msgs::TransformStamped ts;
    ts.header = header;
    ts.child_frame_id = child_frame_id + "_" + std::to_string(k);
    ts.transform = toTransformMsg(result.pose_at(t));
    frames.transforms.push_back(ts);
  }
  tf_static_pub_.publish(frames);
}

void InterpolationNode::publishStatus(const GenerateTrajectory::Request& req, const GenerateTrajectory::Response& res,
                                      const std::string& source)
{
  GenerationStatus status;
  status.header.stamp = ros::Time::now();
  status.success = res.success;
  status.message = res.message;
  status.source = source;
  // The request's strings may be anything (a refused 10 MB name): the latched status carries
  // them only when they are short names, else their quoted prefix (issue 15, rows 3, 5).
  auto bounded = [](const std::string& text) { return text.size() <= kMaxFrameIdLength ? text : quoted(text); };
  status.curve = bounded(req.curve.empty() ? params_.curve : req.curve);
  status.geometry = bounded(req.geometry.empty() ? params_.geometry : req.geometry);
  status.timing = bounded(req.timing.empty() ? params_.timing : req.timing);
  if (req.waypoints.poses.empty())
  {
    std::lock_guard<std::mutex> lock(buffer_mutex_);
    status.header.frame_id = buffer_frame_;
    status.waypoint_count = static_cast<std::uint32_t>(buffer_.size());
  }
  else
  {
    status.header.frame_id =
        bounded(req.waypoints.header.frame_id.empty() ? params_.frame_id : req.waypoints.header.frame_id);
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

void InterpolationNode::noticeDrops(const std::string& publisher, std::uint32_t seq)
{
  auto it = last_seq_.find(publisher);
  if (it != last_seq_.end() && seq > it->second + 1)
  {
    dropped_waypoints_ += seq - it->second - 1;
    // Throttled: a flood of drops must not become a flood of log lines.
    ROS_WARN_STREAM_THROTTLE(1.0, "~waypoint: " << seq - it->second - 1 << " messages from " << quoted(publisher)
                                                << " were dropped (header.seq jumped from " << it->second << " to "
                                                << seq << "; " << dropped_waypoints_
                                                << " dropped in all); raise ~waypoint_queue_size ("
                                                << params_.waypoint_queue_size << ") or publish more slowly");
  }
  // A publisher that does not number its messages (seq constant) or restarted: no jump.
  last_seq_[publisher] = seq;
}

void InterpolationNode::waypointCallback(const ros::MessageEvent<const geometry_msgs::PoseStamped>& event)
{
  try
  {
    const geometry_msgs::PoseStamped::ConstPtr& msg = event.getMessage();
    noticeDrops(event.getPublisherName(), msg->header.seq);
    geometry_msgs::PoseStamped pose = *msg;
    std::string frame;
    {
      std::lock_guard<std::mutex> lock(buffer_mutex_);
      frame = buffer_frame_;
    }
    if (!pose.header.frame_id.empty())
      validateFrameId(pose.header.frame_id, "waypoint.header.frame_id");
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
    ROS_WARN_STREAM("~waypoint rejected: " << bounded(e.what()));
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
    validateFrameId(frame, "waypoints.header.frame_id");
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
    ROS_WARN_STREAM("~waypoints rejected: " << bounded(e.what()));
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
  // Nothing may leave a timer callback: roscpp would terminate the process.
  try
  {
    broadcastMovingFrame();
  }
  catch (const std::exception& e)
  {
    ROS_ERROR_STREAM_THROTTLE(10.0, "moving frame not broadcast: " << bounded(e.what()));
  }
  catch (...)
  {
    ROS_ERROR_THROTTLE(10.0, "moving frame not broadcast: unexpected error");
  }
}

void InterpolationNode::broadcastMovingFrame()
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
  // In integer nanoseconds: a ros::Duration would throw beyond 2^31 s (a stamp far ahead).
  double t = static_cast<double>(static_cast<std::int64_t>(now.toNSec()) -
                                 static_cast<std::int64_t>(playback->stamp.toNSec())) *
             1e-9;
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

void InterpolationNode::watchdogCallback(const ros::TimerEvent& /*event*/)
{
  try
  {
    if (!ros::master::check())
      return;  // the master is away: wait for it to come back
    // The service is registered once, at start-up: a master that does not know it has
    // restarted since (roscpp re-registers nothing).
    XmlRpc::XmlRpcValue args, result, payload;
    args[0] = ros::this_node::getName();
    args[1] = generate_service_.getService();
    if (ros::master::execute("lookupService", args, result, payload, false))
      return;
    ROS_FATAL_STREAM("the ROS master at " << ros::master::getURI() << " no longer knows "
                                          << ros::this_node::getName() << " (its service "
                                          << generate_service_.getService()
                                          << " is not registered: the master restarted); shutting down with exit "
                                             "status 1 so that the launch file's respawn registers the node anew");
    exit_status_ = 1;
    ros::requestShutdown();
  }
  catch (const std::exception& e)
  {
    ROS_ERROR_STREAM_THROTTLE(10.0, "master watchdog: " << bounded(e.what()));
  }
}

}  // namespace se3_interpolation
