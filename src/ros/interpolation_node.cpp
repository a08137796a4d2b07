#include "se3_interpolation/ros/interpolation_node.h"

#include <malloc.h>
#include <ros/connection_manager.h>
#include <ros/master.h>
#include <ros/network.h>
#include <ros/xmlrpc_manager.h>
#include <ros/this_node.h>
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>
#include <tf2_msgs/TFMessage.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <new>
#include <sstream>
#include <stdexcept>

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

/// ~waypoints messages waiting to be handled (each replaces the buffer, so few are worth keeping).
constexpr std::size_t kWaypointsBacklog = 10;
/// roscpp's queues in front of the backlogs: the intake empties them at once, so they only absorb
/// a moment's stall of its thread; a loss there still counts (a header.seq gap). Bounded by the
/// messages' size: a ~waypoints message may carry ~max_waypoints poses.
constexpr std::uint32_t kWaypointIntakeQueue = 10000;
constexpr std::uint32_t kWaypointsIntakeQueue = 1000;
/// Allocations from this size up are mapped and unmapped on their own (returned to the system
/// when freed): glibc's default raises this threshold after each large free, after which large
/// messages stay in the heap.
constexpr int kMmapThreshold = 128 * 1024;
/// Publishers whose header.seq the intake remembers per topic (forgotten all at once beyond).
constexpr std::size_t kMaxTrackedPublishers = 1000;

std::string bounded(const char* what)
{
  const std::string m(what);
  return m.size() <= kMaxMessageLength ? m : m.substr(0, kMaxMessageLength) + "... (truncated)";
}

/// Where playback is at some instant: the trajectory time, and whether the instant is outside the
/// trajectory's span without looping (before its start or at or after its end: the pose is held).
struct PlaybackPosition
{
  double time = 0.0;
  bool ended = false;
};

/// The playback position at `now` of a trajectory stamped `stamp` spanning [t0, t0 + d]: wrapped
/// into the span when looping, else clamped to it (held at the ends).
PlaybackPosition playbackPosition(const ros::Time& stamp, double t0, double d, const ros::Time& now, bool loop)
{
  // In integer nanoseconds: a ros::Duration would throw beyond 2^31 s (a stamp far ahead).
  const double t =
      static_cast<double>(static_cast<std::int64_t>(now.toNSec()) - static_cast<std::int64_t>(stamp.toNSec())) * 1e-9;
  if (loop && d > 0.0)
  {
    double u = std::fmod(t - t0, d);
    if (u < 0.0)
      u += d;
    return { t0 + u, false };
  }
  return { std::min(std::max(t, t0), t0 + d), t < t0 || t >= t0 + d };
}

/// tf2 ignores one leading '/' in frame ids: so does the collision check.
std::string withoutLeadingSlash(const std::string& frame)
{
  return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame;
}
}  // namespace

InterpolationNode::InterpolationNode(ros::NodeHandle nh, ros::NodeHandle private_nh)
  : nh_(std::move(nh))
  , private_nh_(std::move(private_nh))
  , params_(loadNodeParameters(private_nh_))
  , tf_listener_(tf_buffer_)
  , buffer_frame_(params_.frame_id)
{
  mallopt(M_MMAP_THRESHOLD, kMmapThreshold);
  path_pub_ = private_nh_.advertise<nav_msgs::Path>("path", 1, true);
  trajectory_pub_ = private_nh_.advertise<trajectory_msgs::MultiDOFJointTrajectory>("trajectory", 1, true);
  markers_pub_ = private_nh_.advertise<visualization_msgs::MarkerArray>("markers", 1, true);
  tf_static_pub_ = nh_.advertise<tf2_msgs::TFMessage>("/tf_static", 1, true);
  status_pub_ = private_nh_.advertise<GenerationStatus>("status", 1, true);
  clear_service_ = private_nh_.advertiseService("clear_waypoints", &InterpolationNode::clearWaypoints, this);

  ros::NodeHandle service_nh(private_nh_);
  service_nh.setCallbackQueue(&service_queue_);
  generate_service_ = service_nh.advertiseService("generate", &InterpolationNode::generate, this);
  service_spinner_ = std::make_unique<ros::AsyncSpinner>(params_.service_threads, &service_queue_);
  service_spinner_->start();

  // roscpp's queues only hand the messages over to the backlogs, whose drops are counted; a loss
  // in roscpp's queue shows as a header.seq gap.
  waypoint_backlog_ = std::make_unique<MessageBacklog<geometry_msgs::PoseStamped::ConstPtr>>(
      static_cast<std::size_t>(params_.waypoint_queue_size),
      [this](const geometry_msgs::PoseStamped::ConstPtr& msg) { waypointCallback(msg); });
  waypoints_backlog_ = std::make_unique<MessageBacklog<geometry_msgs::PoseArray::ConstPtr>>(
      kWaypointsBacklog, [this](const geometry_msgs::PoseArray::ConstPtr& msg) { waypointsCallback(msg); });
  // One intake thread per topic: a burst on one never fills roscpp's queue of the other.
  ros::NodeHandle intake_nh(private_nh_);
  intake_nh.setCallbackQueue(&intake_queue_);
  waypoint_sub_ = intake_nh.subscribe("waypoint", kWaypointIntakeQueue, &InterpolationNode::waypointIntake, this);
  intake_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &intake_queue_);
  intake_spinner_->start();
  ros::NodeHandle array_intake_nh(private_nh_);
  array_intake_nh.setCallbackQueue(&array_intake_queue_);
  waypoints_sub_ =
      array_intake_nh.subscribe("waypoints", kWaypointsIntakeQueue, &InterpolationNode::waypointsIntake, this);
  array_intake_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &array_intake_queue_);
  array_intake_spinner_->start();

  ros::NodeHandle tf_nh(private_nh_);
  tf_nh.setCallbackQueue(&tf_queue_);
  tf_timer_ = tf_nh.createTimer(ros::Duration(1.0 / params_.tf_rate), &InterpolationNode::tfTimerCallback, this);
  tf_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &tf_queue_);
  tf_spinner_->start();

  if (params_.publish_tf)
    tf_watch_sub_ = tf_nh.subscribe("/tf", 100, &InterpolationNode::tfWatchCallback, this);

  // Started from the validated start-up values, so that a refused ~curve is not read back.
  reconfigure_server_ =
      std::make_unique<dynamic_reconfigure::Server<InterpolationNodeConfig>>(reconfigure_mutex_, private_nh_);
  reconfigure_server_->updateConfig(currentConfig());
  reconfigure_server_->setCallback(
      [this](InterpolationNodeConfig& config, std::uint32_t level) { reconfigure(config, level); });

  services_ = { generate_service_.getService(), clear_service_.getService(),
                private_nh_.resolveName("set_parameters") };
  ros::NodeHandle watchdog_nh(private_nh_);
  watchdog_nh.setCallbackQueue(&watchdog_queue_);
  if (params_.master_check_period > 0.0)
  {
    ros::param::get("/run_id", run_id_);
    watchdog_timer_ = watchdog_nh.createTimer(ros::Duration(params_.master_check_period),
                                              &InterpolationNode::watchdogCallback, this);
  }
  maintenance_timer_ = watchdog_nh.createWallTimer(ros::WallDuration(1.0), &InterpolationNode::maintenanceCallback, this);
  watchdog_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &watchdog_queue_);
  watchdog_spinner_->start();
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
  reconfigure_server_.reset();
  watchdog_spinner_->stop();
  tf_spinner_->stop();
  intake_spinner_->stop();
  array_intake_spinner_->stop();
  waypoint_backlog_.reset();
  waypoints_backlog_.reset();
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
    if (req.waypoints.poses.empty() && req.waypoint_frames.empty())
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
    if (!req.waypoint_frames.empty())
    {
      if (poses.size() + req.waypoint_frames.size() > params_.limits.max_waypoints)
        throw LimitExceededError("waypoints: " + std::to_string(poses.size()) + " poses and " +
                                 std::to_string(req.waypoint_frames.size()) +
                                 " waypoint_frames given; the limit (~max_waypoints) is " +
                                 std::to_string(params_.limits.max_waypoints));
      const std::vector<geometry_msgs::Pose> taught = lookUpWaypointFrames(req.waypoint_frames, frame);
      poses.insert(poses.end(), taught.begin(), taught.end());
    }
    const std::string child = req.child_frame_id.empty() ? params_.child_frame_id : req.child_frame_id;
    validateFrameId(child, "child_frame_id");
    if (child == frame)
      throw InvalidInputError("child_frame_id: " + quotedText(child) + " is also the waypoints' frame");

    const ResponseOutputs outputs = parseResponseOutputs(req.outputs);
    TrajectoryRequest r = fromMsg(req, poses);
    applyRequestDefaults(&r);
    ros::Time stamp = req.waypoints.header.stamp;
    if (req.from_current)
    {
      // The switch time T_s: the request's stamp, else ~replan_lead from now; times count from it.
      if (stamp.isZero())
      {
        std::lock_guard<std::mutex> lock(params_mutex_);
        stamp = ros::Time::now() + ros::Duration(params_.replan_lead);
      }
      startFromCurrent(stamp, frame, child, &r);
    }
    const std::chrono::steady_clock::time_point planning = std::chrono::steady_clock::now();
    const TrajectoryResult result = se3_interpolation::generate(r, params_.limits);
    const std::chrono::steady_clock::time_point filling = std::chrono::steady_clock::now();

    std_msgs::Header header;
    header.frame_id = frame;
    header.stamp = stamp.isZero() ? ros::Time::now() : stamp;
    validateStampedSpan(header.stamp.toSec(), result.start_time, result.start_time + result.duration,
                        "waypoints.header.stamp");

    if (outputs.path)
      toMsg(result, header, res.path);
    if (outputs.trajectory)
      toMsg(result, header, child, res.trajectory);
    // The service's latency apart from transport (docs/performance.md "Service latency"):
    // rosconsole logger ros.se3_interpolation.timing at debug level.
    ROS_DEBUG_NAMED("timing", "generate: %zu samples, planner %.1f ms, response messages %.1f ms",
                    result.samples.size(), 1e3 * std::chrono::duration<double>(filling - planning).count(),
                    1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - filling).count());
    copyFigures(result, res);
    res.success = true;
    std::ostringstream msg;
    msg << result.samples.size() << " samples over " << result.duration << " s";
    if (result.time_scale > 1.0)
      msg << " (time stretched x" << result.time_scale << " to meet the bounds)";
    if (result.recovery_time > 0.0)
      msg << "; the start state exceeds a bound: every bound holds from t = " << result.recovery_time
          << " s on (recovery_time)";
    res.message = msg.str();
    if (req.publish)
    {
      // The topics carry both forms whatever the response omits.
      nav_msgs::Path path;
      trajectory_msgs::MultiDOFJointTrajectory trajectory;
      publish(result, outputs.path ? res.path : toMsg(result, header, path),
              outputs.trajectory ? res.trajectory : toMsg(result, header, child, trajectory), header, child);
    }
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
    res.message = bounded(withLimitPrefix(e.what(), "~").c_str());
  }
  catch (...)
  {
    res = GenerateTrajectory::Response();
    res.success = false;
    res.message = "unexpected error while generating the trajectory";
  }
}

void InterpolationNode::applyRequestDefaults(TrajectoryRequest* request) const
{
  TrajectoryRequest& r = *request;
  std::lock_guard<std::mutex> lock(params_mutex_);
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
}

std::vector<geometry_msgs::Pose> InterpolationNode::lookUpWaypointFrames(const std::vector<std::string>& frames,
                                                                         const std::string& target)
{
  std::vector<geometry_msgs::Pose> poses;
  poses.reserve(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i)
  {
    const std::string field = indexedField("waypoint_frames", i);
    validateFrameId(frames[i], field);
    geometry_msgs::TransformStamped t;
    try
    {
      // The latest transform; tf2's listener thread fills the buffer while this one waits.
      t = tf_buffer_.lookupTransform(target, frames[i], ros::Time(0), ros::Duration(params_.tf_timeout));
    }
    catch (const tf2::TransformException& e)
    {
      std::ostringstream why;
      why << field << ": no transform from " << quotedText(frames[i]) << " to " << quotedText(target) << " within ~tf_timeout = "
          << params_.tf_timeout << " s (tf2: " << bounded(e.what()) << ")";
      throw InvalidInputError(why.str());
    }
    geometry_msgs::Pose p;
    p.position.x = t.transform.translation.x;
    p.position.y = t.transform.translation.y;
    p.position.z = t.transform.translation.z;
    p.orientation = t.transform.rotation;
    poses.push_back(p);
  }
  return poses;
}

void InterpolationNode::publish(const TrajectoryResult& result, const nav_msgs::Path& path,
                                const trajectory_msgs::MultiDOFJointTrajectory& trajectory,
                                const std_msgs::Header& header, const std::string& child_frame_id)
{
  std::lock_guard<std::mutex> publishing(publish_mutex_);
  path_pub_.publish(path);
  trajectory_pub_.publish(trajectory);
  markers_pub_.publish(toMarkerArray(result, result.waypoints, header, params_.marker_axes, params_.axis_length));

  auto playback = std::make_shared<Playback>();
  playback->point_at = result.point_at;
  playback->state_at = result.state_at;
  playback->stamp = header.stamp;
  playback->start_time = result.start_time;
  playback->duration = result.duration;
  playback->frame_id = header.frame_id;
  playback->child_frame_id = child_frame_id;
  {
    std::lock_guard<std::mutex> lock(playback_mutex_);
    // Until the new trajectory starts the frame keeps showing the one playing now (a replan's
    // switch time lies ~replan_lead ahead); older pending ones are no longer reachable.
    if (playback_ && playback_->child_frame_id == child_frame_id)
    {
      auto current = std::make_shared<Playback>(*playback_);
      if (current->previous && ros::Time::now() >= current->stamp + ros::Duration(current->start_time))
        current->previous.reset();
      playback->previous = current;
    }
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
    toMsg(result.point_at(t), ts.transform);
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
  // them only when they are short names, else their quoted prefix.
  auto bounded = [](const std::string& text) { return text.size() <= kMaxFrameIdLength ? text : quotedText(text); };
  {
    std::lock_guard<std::mutex> lock(params_mutex_);
    status.curve = bounded(req.curve.empty() ? params_.curve : req.curve);
    status.geometry = bounded(req.geometry.empty() ? params_.geometry : req.geometry);
    status.timing = bounded(req.timing.empty() ? params_.timing : req.timing);
  }
  if (req.waypoints.poses.empty() && req.waypoint_frames.empty())
  {
    std::lock_guard<std::mutex> lock(buffer_mutex_);
    status.header.frame_id = buffer_frame_;
    status.waypoint_count = static_cast<std::uint32_t>(buffer_.size());
  }
  else
  {
    status.header.frame_id =
        bounded(req.waypoints.header.frame_id.empty() ? params_.frame_id : req.waypoints.header.frame_id);
    status.waypoint_count = static_cast<std::uint32_t>(req.waypoints.poses.size() + req.waypoint_frames.size());
  }
  copyFigures(res, status);
  status.dropped_waypoint_messages = droppedWaypointMessages();
  status.dropped_waypoints_messages = droppedWaypointsMessages();
  status_pub_.publish(status);
}

bool InterpolationNode::clearWaypoints(std_srvs::Trigger::Request& /*req*/, std_srvs::Trigger::Response& res)
{
  std::size_t n = 0;
  std::string frame;
  {
    std::lock_guard<std::mutex> lock(buffer_mutex_);
    n = buffer_.size();
    buffer_.clear();
    frame = buffer_frame_;
  }
  {
    std::lock_guard<std::mutex> publishing(publish_mutex_);
    holdPlayback();
    nav_msgs::Path empty;
    empty.header.stamp = ros::Time::now();
    empty.header.frame_id = frame;
    path_pub_.publish(empty);
    visualization_msgs::MarkerArray deletion;
    visualization_msgs::Marker all;
    all.header = empty.header;
    all.action = visualization_msgs::Marker::DELETEALL;
    deletion.markers.push_back(all);
    markers_pub_.publish(deletion);
  }
  res.success = true;
  res.message = "cleared " + std::to_string(n) + " waypoints; playback stopped, path and markers cleared";
  return true;
}

void InterpolationNode::holdPlayback()
{
  std::lock_guard<std::mutex> lock(playback_mutex_);
  if (!playback_)
    return;
  const ros::Time now = ros::Time::now();
  bool loop = false;
  {
    std::lock_guard<std::mutex> params_lock(params_mutex_);
    loop = params_.loop;
  }
  const Pose<double> held = playback_->point_at(
      playbackPosition(playback_->stamp, playback_->start_time, playback_->duration, now, loop).time);
  auto hold = std::make_shared<Playback>(*playback_);
  hold->point_at = [held](double) { return held; };
  hold->stamp = now;
  hold->start_time = 0.0;
  hold->duration = 0.0;
  playback_ = hold;
}

std::uint64_t InterpolationNode::seqGap(std::map<std::string, std::uint32_t>* last_seq,
                                       const std::string& publisher, std::uint32_t seq)
{
  if (last_seq->size() >= kMaxTrackedPublishers && last_seq->count(publisher) == 0)
    last_seq->clear();
  auto it = last_seq->find(publisher);
  std::uint64_t gap = 0;
  // A publisher that does not number its messages (seq constant) or restarted: no gap.
  if (it != last_seq->end() && seq > it->second + 1)
    gap = seq - it->second - 1;
  (*last_seq)[publisher] = seq;
  return gap;
}

void InterpolationNode::waypointIntake(const ros::MessageEvent<const geometry_msgs::PoseStamped>& event)
{
  const geometry_msgs::PoseStamped::ConstPtr& msg = event.getMessage();
  waypoint_gaps_ += seqGap(&waypoint_seq_, event.getPublisherName(), msg->header.seq);
  waypoint_backlog_->push(msg);
}

void InterpolationNode::waypointsIntake(const ros::MessageEvent<const geometry_msgs::PoseArray>& event)
{
  const geometry_msgs::PoseArray::ConstPtr& msg = event.getMessage();
  waypoints_gaps_ += seqGap(&waypoints_seq_, event.getPublisherName(), msg->header.seq);
  waypoints_backlog_->push(msg);
}

std::uint64_t InterpolationNode::droppedWaypointMessages() const
{
  return waypoint_gaps_ + waypoint_backlog_->dropped();
}

std::uint64_t InterpolationNode::droppedWaypointsMessages() const
{
  return waypoints_gaps_ + waypoints_backlog_->dropped();
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
    if (!pose.header.frame_id.empty())
      validateFrameId(pose.header.frame_id, "waypoint.header.frame_id");
    if (!pose.header.frame_id.empty() && pose.header.frame_id != frame)
      pose = tf_buffer_.transform(pose, frame, ros::Duration(params_.tf_timeout));
    validatePose(fromMsg(pose.pose), "waypoint.pose");
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
      validatePose(fromMsg(msg->poses[i]), "waypoints.poses[" + std::to_string(i) + "]");
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
  req.from_current = params_.replan_from_current;
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
  const ros::Time now = ros::Time::now();
  const std::shared_ptr<const Playback> playback = playbackAt(now);
  if (!playback || !params_.publish_tf)
    return;
  if (now <= last_tf_stamp_)
    return;  // TF stamps never repeat or go backwards
  bool ended = false;
  const double t = playbackClock(*playback, now, &ended);
  geometry_msgs::TransformStamped ts;
  ts.header.stamp = now;
  ts.header.frame_id = playback->frame_id;
  ts.child_frame_id = playback->child_frame_id;
  toMsg(playback->point_at(t), ts.transform);
  tf_broadcaster_.sendTransform(ts);
  last_tf_stamp_ = now;
}

void InterpolationNode::tfWatchCallback(const ros::MessageEvent<const tf2_msgs::TFMessage>& event)
{
  const std::string& publisher = event.getPublisherName();  // the connection header's callerid
  if (publisher == ros::this_node::getName())
    return;  // our own broadcasts (also under a nodelet manager: its name is ours)
  std::shared_ptr<const Playback> playback;
  {
    std::lock_guard<std::mutex> lock(playback_mutex_);
    playback = playback_;
  }
  // const: a non-const std::string would pick std::quoted by argument-dependent lookup.
  const std::string child = playback ? playback->child_frame_id : params_.child_frame_id;
  for (const auto& t : event.getMessage()->transforms)
  {
    if (withoutLeadingSlash(t.child_frame_id) != child)
      continue;
    // Throttled: a colliding publisher at 50 Hz must not become 50 log lines a second.
    ROS_WARN_STREAM_THROTTLE(5.0, "TF collision: " << quotedText(publisher) << " also publishes this node's moving frame "
                                                   << quotedText(child) << " (parent " << quotedText(t.header.frame_id)
                                                   << ") on /tf; give each instance its own ~child_frame_id "
                                                      "(launch argument child_frame_id)");
    return;
  }
}

InterpolationNodeConfig InterpolationNode::currentConfig() const
{
  std::lock_guard<std::mutex> lock(params_mutex_);
  InterpolationNodeConfig c = InterpolationNodeConfig::__getDefault__();
  c.curve = params_.curve;
  c.geometry = params_.geometry;
  c.parameterization = params_.parameterization;
  c.timing = params_.timing;
  c.max_linear_velocity = params_.max_linear_velocity;
  c.max_angular_velocity = params_.max_angular_velocity;
  c.max_linear_acceleration = params_.max_linear_acceleration;
  c.max_angular_acceleration = params_.max_angular_acceleration;
  c.duration = params_.duration;
  c.sample_count = params_.sample_count;
  c.blend_radius = params_.blend_radius;
  c.loop = params_.loop;
  c.tf_rate = params_.tf_rate;
  return c;
}

void InterpolationNode::reconfigure(InterpolationNodeConfig& config, std::uint32_t /*level*/)
{
  const InterpolationNodeConfig old = currentConfig();
  // A refused value is warned and replaced by the old one, which the server then publishes.
  auto text = [](std::string* value, const std::string& previous, const char* name) {
    if (*value == previous)
      return;
    const std::string why = stringParameterError(name, *value);
    if (why.empty())
      return;
    ROS_WARN_STREAM("dynamic_reconfigure: " << why << "; keeping " << quotedText(previous));
    *value = previous;
  };
  auto number = [](auto* value, auto previous, const char* name) {
    if (*value == previous)
      return;
    const std::string why = numberParameterError(name, static_cast<double>(*value));
    if (why.empty())
      return;
    ROS_WARN_STREAM("dynamic_reconfigure: " << why << "; keeping " << previous);
    *value = previous;
  };
  text(&config.curve, old.curve, "curve");
  text(&config.geometry, old.geometry, "geometry");
  text(&config.parameterization, old.parameterization, "parameterization");
  text(&config.timing, old.timing, "timing");
  number(&config.max_linear_velocity, old.max_linear_velocity, "max_linear_velocity");
  number(&config.max_angular_velocity, old.max_angular_velocity, "max_angular_velocity");
  number(&config.max_linear_acceleration, old.max_linear_acceleration, "max_linear_acceleration");
  number(&config.max_angular_acceleration, old.max_angular_acceleration, "max_angular_acceleration");
  number(&config.duration, old.duration, "duration");
  number(&config.sample_count, old.sample_count, "sample_count");
  number(&config.blend_radius, old.blend_radius, "blend_radius");
  number(&config.tf_rate, old.tf_rate, "tf_rate");
  {
    std::lock_guard<std::mutex> lock(params_mutex_);
    params_.curve = config.curve;
    params_.geometry = config.geometry;
    params_.parameterization = config.parameterization;
    params_.timing = config.timing;
    params_.max_linear_velocity = config.max_linear_velocity;
    params_.max_angular_velocity = config.max_angular_velocity;
    params_.max_linear_acceleration = config.max_linear_acceleration;
    params_.max_angular_acceleration = config.max_angular_acceleration;
    params_.duration = config.duration;
    params_.sample_count = config.sample_count;
    params_.blend_radius = config.blend_radius;
    params_.loop = config.loop;
    params_.tf_rate = config.tf_rate;
  }
  if (config.tf_rate != old.tf_rate)
    tf_timer_.setPeriod(ros::Duration(1.0 / config.tf_rate));
  ROS_INFO_STREAM("dynamic_reconfigure: curve " << config.curve << ", geometry " << config.geometry
                                                << ", parameterization " << config.parameterization << ", timing "
                                                << config.timing << ", loop " << (config.loop ? "on" : "off")
                                                << ", tf_rate " << config.tf_rate << " Hz");
}

std::shared_ptr<const InterpolationNode::Playback> InterpolationNode::playbackAt(const ros::Time& time) const
{
  std::shared_ptr<const Playback> p;
  {
    std::lock_guard<std::mutex> lock(playback_mutex_);
    p = playback_;
  }
  // In integer nanoseconds: a ros::Duration would throw beyond 2^31 s (a stamp far ahead).
  while (p && p->previous &&
         static_cast<std::int64_t>(time.toNSec()) <
             static_cast<std::int64_t>(p->stamp.toNSec()) + static_cast<std::int64_t>(std::llround(p->start_time * 1e9)))
    p = p->previous;
  return p;
}

double InterpolationNode::playbackClock(const Playback& playback, const ros::Time& time, bool* ended) const
{
  bool loop = false;
  {
    std::lock_guard<std::mutex> lock(params_mutex_);
    loop = params_.loop;
  }
  const PlaybackPosition position = playbackPosition(playback.stamp, playback.start_time, playback.duration, time, loop);
  *ended = position.ended;
  return position.time;
}

void InterpolationNode::startFromCurrent(const ros::Time& switch_time, const std::string& frame,
                                         const std::string& child, TrajectoryRequest* r) const
{
  const std::shared_ptr<const Playback> playback = playbackAt(switch_time);
  if (!playback || playback->child_frame_id != child || !playback->state_at)
    return;  // nothing plays on this frame: the trajectory starts at waypoints[0]
  if (playback->frame_id != frame)
    throw InvalidInputError("from_current: the moving frame " + quotedText(child) + " plays in frame " +
                            quotedText(playback->frame_id) + ", not in the waypoints' frame " + quotedText(frame) +
                            " (give waypoints in that frame, or from_current false)");
  bool ended = false;
  const double t = playbackClock(*playback, switch_time, &ended);
  const TrajectorySample s = playback->state_at(t);
  StartState start;
  start.pose = s.pose;
  if (!ended)
  {
    start.velocity = s.velocity;
    start.acceleration = s.acceleration;
  }
  r->start_state = start;
}

void InterpolationNode::watchdogCallback(const ros::TimerEvent& /*event*/)
{
  try
  {
    if (!ros::master::check())
      return;  // the master is away: wait for it to come back
    if (!masterForgotUs())
      return;
    ROS_WARN_STREAM("the ROS master at " << ros::master::getURI() << " no longer knows " << ros::this_node::getName()
                                         << " (it restarted); registering again");
    ROS_WARN_STREAM("registered again with the new master: " << registerAgain());
  }
  catch (const std::exception& e)
  {
    ROS_ERROR_STREAM_THROTTLE(10.0, "master watchdog: " << bounded(e.what()));
  }
}

bool InterpolationNode::masterForgotUs()
{
  // A failed call (the master gone again meanwhile) counts as forgotten: registering again is
  // harmless (the master's registrations are idempotent) and is retried at the next check.
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = generate_service_.getService();
  if (!ros::master::execute("lookupService", args, result, payload, false))
    return true;
  if (run_id_.empty())
    return false;
  XmlRpc::XmlRpcValue param_args, param_result, run_id;
  param_args[0] = ros::this_node::getName();
  param_args[1] = "/run_id";
  if (!ros::master::execute("getParam", param_args, param_result, run_id, false) ||
      run_id.getType() != XmlRpc::XmlRpcValue::TypeString)
    return true;
  if (static_cast<std::string>(run_id) == run_id_)
    return false;
  run_id_ = static_cast<std::string>(run_id);
  return true;
}

namespace
{
/// Calls `method` of this process's own slave API (its XML-RPC server) and returns the value of
/// its [code, message, value] answer; throws when it fails.
XmlRpc::XmlRpcValue callOwnSlaveApi(const std::string& method, XmlRpc::XmlRpcValue& args)
{
  std::string host;
  std::uint32_t port = 0;
  if (!ros::network::splitURI(ros::XMLRPCManager::instance()->getServerURI(), host, port))
    throw std::runtime_error("cannot parse this node's XML-RPC URI");
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue result;
  if (!client.execute(method.c_str(), args, result) || result.getType() != XmlRpc::XmlRpcValue::TypeArray ||
      result.size() != 3 || static_cast<int>(result[0]) != 1)
    throw std::runtime_error("this node's XML-RPC " + method + " failed");
  return result[2];
}
}  // namespace

std::string InterpolationNode::registerAgain()
{
  const std::string caller = ros::this_node::getName();
  const std::string caller_api = ros::XMLRPCManager::instance()->getServerURI();
  NodeParameters params;
  {
    std::lock_guard<std::mutex> lock(params_mutex_);
    params = params_;
  }
  writeNodeParameters(private_nh_, params);
  std::size_t failed = 0;
  auto registerOne = [&](const char* method, const std::string& name, const std::string& api) {
    XmlRpc::XmlRpcValue args, result, payload;
    args[0] = caller;
    args[1] = name;
    args[2] = api;
    args[3] = caller_api;
    if (!ros::master::execute(method, args, result, payload, false))
    {
      ++failed;
      ROS_WARN_STREAM("master " << method << " " << name << " failed; retried at the next check");
    }
    return payload;
  };
  // Publications first, so that the subscriptions below find this process's own publishers too.
  XmlRpc::XmlRpcValue own_args;
  own_args[0] = caller;
  XmlRpc::XmlRpcValue publications = callOwnSlaveApi("getPublications", own_args);
  for (int i = 0; i < publications.size(); ++i)
    registerOne("registerPublisher", publications[i][0], publications[i][1]);
  XmlRpc::XmlRpcValue subscriptions = callOwnSlaveApi("getSubscriptions", own_args);
  for (int i = 0; i < subscriptions.size(); ++i)
  {
    const std::string topic = subscriptions[i][0];
    XmlRpc::XmlRpcValue publishers = registerOne("registerSubscriber", topic, subscriptions[i][1]);
    if (publishers.getType() != XmlRpc::XmlRpcValue::TypeArray)
      continue;
    // What the master would send a subscriber: connects to the publishers it knows.
    XmlRpc::XmlRpcValue update;
    update[0] = std::string("/master");
    update[1] = topic;
    update[2] = publishers;
    callOwnSlaveApi("publisherUpdate", update);
  }
  const std::string service_api =
      "rosrpc://" + ros::network::getHost() + ":" + std::to_string(ros::ConnectionManager::instance()->getTCPPort());
  for (const std::string& service : services_)
    registerOne("registerService", service, service_api);
  std::ostringstream summary;
  summary << publications.size() << " publications, " << subscriptions.size() << " subscriptions, "
          << services_.size() << " services and the parameters under " << private_nh_.getNamespace();
  if (failed > 0)
    summary << " (" << failed << " registrations failed)";
  return summary.str();
}

void InterpolationNode::maintenanceCallback(const ros::WallTimerEvent& /*event*/)
{
  const std::uint64_t waypoint = droppedWaypointMessages();
  const std::uint64_t waypoints = droppedWaypointsMessages();
  if (waypoint != reported_waypoint_drops_ || waypoints != reported_waypoints_drops_)
  {
    ROS_WARN_STREAM("dropped waypoint messages: ~waypoint " << waypoint - reported_waypoint_drops_
                                                            << " since the last report (" << waypoint
                                                            << " in all), ~waypoints "
                                                            << waypoints - reported_waypoints_drops_ << " ("
                                                            << waypoints
                                                            << " in all); they came faster than the node handles "
                                                               "them: raise ~waypoint_queue_size ("
                                                            << params_.waypoint_queue_size
                                                            << ") or publish more slowly");
    reported_waypoint_drops_ = waypoint;
    reported_waypoints_drops_ = waypoints;
  }
  // Large messages (floods, 1e5-sample trajectories and their serialised copies) are freed on
  // many threads; glibc keeps the freed pages unless asked.
  malloc_trim(0);
}

}  // namespace se3_interpolation
