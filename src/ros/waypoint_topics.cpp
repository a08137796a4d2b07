#include "se3_interpolation/ros/waypoint_topics.h"

#include <tf2_geometry_msgs/tf2_geometry_msgs.h>

#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/ros/conversions.h"

namespace se3_interpolation
{
namespace
{
/// ~waypoints messages waiting to be handled (each replaces the buffer, so few are worth keeping).
constexpr std::size_t kWaypointsBacklog = 10;
/// roscpp's queues in front of the backlogs: the intake empties them at once, so they only absorb
/// a moment's stall of its thread; a loss there still counts (a header.seq gap). Bounded by the
/// messages' size: a ~waypoints message may carry ~max_waypoints poses.
constexpr std::uint32_t kWaypointIntakeQueue = 10000;
constexpr std::uint32_t kWaypointsIntakeQueue = 1000;

std::string limitMessage(std::size_t capacity)
{
  return "the buffer holds ~max_waypoints = " + std::to_string(capacity) + " waypoints";
}
}  // namespace

WaypointTopics::WaypointTopics(ros::NodeHandle private_nh, const NodeParameters& params, const tf2_ros::Buffer& tf,
                               std::function<void()> on_change)
  : tf_(tf)
  , tf_timeout_(params.tf_timeout)
  , queue_size_(params.waypoint_queue_size)
  , default_frame_(params.frame_id)
  , on_change_(std::move(on_change))
  , buffer_(static_cast<std::size_t>(params.max_waypoints), params.frame_id)
{
  waypoint_backlog_ = std::make_unique<MessageBacklog<geometry_msgs::PoseStamped::ConstPtr>>(
      static_cast<std::size_t>(queue_size_),
      [this](const geometry_msgs::PoseStamped::ConstPtr& msg) { handleWaypoint(msg); });
  waypoints_backlog_ = std::make_unique<MessageBacklog<geometry_msgs::PoseArray::ConstPtr>>(
      kWaypointsBacklog, [this](const geometry_msgs::PoseArray::ConstPtr& msg) { handleWaypoints(msg); });
  // One intake thread per topic: a burst on one never fills roscpp's queue of the other.
  ros::NodeHandle waypoint_nh(private_nh);
  waypoint_nh.setCallbackQueue(&waypoint_queue_);
  waypoint_sub_ = waypoint_nh.subscribe("waypoint", kWaypointIntakeQueue, &WaypointTopics::waypointIntake, this);
  waypoint_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &waypoint_queue_);
  waypoint_spinner_->start();
  ros::NodeHandle waypoints_nh(private_nh);
  waypoints_nh.setCallbackQueue(&waypoints_queue_);
  waypoints_sub_ = waypoints_nh.subscribe("waypoints", kWaypointsIntakeQueue, &WaypointTopics::waypointsIntake, this);
  waypoints_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &waypoints_queue_);
  waypoints_spinner_->start();
}

WaypointTopics::~WaypointTopics()
{
  waypoint_spinner_->stop();
  waypoints_spinner_->stop();
  waypoint_backlog_.reset();
  waypoints_backlog_.reset();
}

void WaypointTopics::waypointIntake(const ros::MessageEvent<const geometry_msgs::PoseStamped>& event)
{
  const geometry_msgs::PoseStamped::ConstPtr& msg = event.getMessage();
  waypoint_gaps_ += waypoint_seq_.observe(event.getPublisherName(), msg->header.seq);
  waypoint_backlog_->push(msg);
}

void WaypointTopics::waypointsIntake(const ros::MessageEvent<const geometry_msgs::PoseArray>& event)
{
  const geometry_msgs::PoseArray::ConstPtr& msg = event.getMessage();
  waypoints_gaps_ += waypoints_seq_.observe(event.getPublisherName(), msg->header.seq);
  waypoints_backlog_->push(msg);
}

std::uint64_t WaypointTopics::droppedWaypoint() const
{
  return waypoint_gaps_ + waypoint_backlog_->dropped();
}

std::uint64_t WaypointTopics::droppedWaypoints() const
{
  return waypoints_gaps_ + waypoints_backlog_->dropped();
}

void WaypointTopics::handleWaypoint(const geometry_msgs::PoseStamped::ConstPtr& msg)
{
  try
  {
    geometry_msgs::PoseStamped pose = *msg;
    const std::string frame = buffer_.frameId();
    if (!pose.header.frame_id.empty())
      validateFrameId(pose.header.frame_id, "waypoint.header.frame_id");
    if (!pose.header.frame_id.empty() && pose.header.frame_id != frame)
      pose = tf_.transform(pose, frame, ros::Duration(tf_timeout_));
    validatePose(fromMsg(pose.pose), "waypoint.pose");
    std::size_t n = 0;
    if (!buffer_.append(pose.pose, &n, msg->header.stamp.toSec()))
      throw LimitExceededError(limitMessage(buffer_.capacity()));
    ROS_DEBUG_STREAM("buffered waypoint " << n - 1);
    if (n >= 2 && on_change_)
      on_change_();
  }
  catch (const std::exception& e)
  {
    ROS_WARN_STREAM("~waypoint rejected: " << boundedMessage(e.what()));
  }
}

void WaypointTopics::handleWaypoints(const geometry_msgs::PoseArray::ConstPtr& msg)
{
  try
  {
    for (std::size_t i = 0; i < msg->poses.size(); ++i)
      validatePose(fromMsg(msg->poses[i]), indexedField("waypoints.poses", i));
    const std::string frame = msg->header.frame_id.empty() ? default_frame_ : msg->header.frame_id;
    validateFrameId(frame, "waypoints.header.frame_id");
    if (!buffer_.replace(msg->poses, frame))
      throw LimitExceededError("more than ~max_waypoints = " + std::to_string(buffer_.capacity()) + " waypoints");
    if (msg->poses.size() >= 2 && on_change_)
      on_change_();
  }
  catch (const std::exception& e)
  {
    ROS_WARN_STREAM("~waypoints rejected: " << boundedMessage(e.what()));
  }
}

void WaypointTopics::reportDrops()
{
  const std::uint64_t waypoint = droppedWaypoint();
  const std::uint64_t waypoints = droppedWaypoints();
  if (waypoint == reported_waypoint_ && waypoints == reported_waypoints_)
    return;
  ROS_WARN_STREAM("dropped waypoint messages: ~waypoint " << waypoint - reported_waypoint_ << " since the last report ("
                                                          << waypoint << " in all), ~waypoints "
                                                          << waypoints - reported_waypoints_ << " (" << waypoints
                                                          << " in all); they came faster than the node handles them: "
                                                             "raise ~waypoint_queue_size ("
                                                          << queue_size_ << ") or publish more slowly");
  reported_waypoint_ = waypoint;
  reported_waypoints_ = waypoints;
}

}  // namespace se3_interpolation
