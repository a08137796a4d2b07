// ros/waypoint_topics.h: the waypoint buffer's topics. ~waypoint (geometry_msgs/PoseStamped)
// appends one pose, transformed with tf2 into the buffer's frame (waiting up to ~tf_timeout on its
// own thread); ~waypoints (geometry_msgs/PoseArray) replaces the buffer. Each topic is taken off
// roscpp's queue at once by an intake thread into a bounded backlog (MessageBacklog, handled by
// its own worker thread), so that a burst on one never delays the other or anything else.
// Every message the node does not handle is counted: those a backlog dropped to make room
// (~waypoint_queue_size, 10 for ~waypoints) and those lost before it (gaps of header.seq).
#pragma once

#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>

#include <atomic>
#include <functional>
#include <memory>
#include <string>

#include "se3_interpolation/execution/sequence_gaps.h"
#include "se3_interpolation/execution/waypoint_buffer.h"
#include "se3_interpolation/ros/message_backlog.h"
#include "se3_interpolation/ros/node_parameters.h"

namespace se3_interpolation
{
class WaypointTopics
{
public:
  using Buffer = WaypointBuffer<geometry_msgs::Pose>;

  /// Subscribes ~waypoint and ~waypoints on `private_nh`; `on_change` is called (on a worker
  /// thread) after every change that leaves at least 2 waypoints in the buffer.
  WaypointTopics(ros::NodeHandle private_nh, const NodeParameters& params, const tf2_ros::Buffer& tf,
                 std::function<void()> on_change);
  ~WaypointTopics();

  Buffer& buffer() { return buffer_; }
  std::string waypointTopic() const { return waypoint_sub_.getTopic(); }
  std::string waypointsTopic() const { return waypoints_sub_.getTopic(); }

  /// Messages not handled so far, of ~waypoint and of ~waypoints.
  std::uint64_t droppedWaypoint() const;
  std::uint64_t droppedWaypoints() const;
  /// Warns about the messages dropped since the last report, if any (the node calls it once a second).
  void reportDrops();

private:
  void waypointIntake(const ros::MessageEvent<const geometry_msgs::PoseStamped>& event);
  void waypointsIntake(const ros::MessageEvent<const geometry_msgs::PoseArray>& event);
  void handleWaypoint(const geometry_msgs::PoseStamped::ConstPtr& msg);
  void handleWaypoints(const geometry_msgs::PoseArray::ConstPtr& msg);

  const tf2_ros::Buffer& tf_;
  const double tf_timeout_;
  const int queue_size_;
  const std::string default_frame_;
  std::function<void()> on_change_;
  Buffer buffer_;
  SequenceGaps waypoint_seq_;   ///< ~waypoint's intake thread only
  SequenceGaps waypoints_seq_;  ///< ~waypoints' intake thread only
  std::atomic<std::uint64_t> waypoint_gaps_{ 0 };
  std::atomic<std::uint64_t> waypoints_gaps_{ 0 };
  std::uint64_t reported_waypoint_ = 0;  ///< the totals of the latest warning
  std::uint64_t reported_waypoints_ = 0;
  std::unique_ptr<MessageBacklog<geometry_msgs::PoseStamped::ConstPtr>> waypoint_backlog_;
  std::unique_ptr<MessageBacklog<geometry_msgs::PoseArray::ConstPtr>> waypoints_backlog_;
  ros::CallbackQueue waypoint_queue_;
  ros::CallbackQueue waypoints_queue_;
  ros::Subscriber waypoint_sub_;
  ros::Subscriber waypoints_sub_;
  std::unique_ptr<ros::AsyncSpinner> waypoint_spinner_;
  std::unique_ptr<ros::AsyncSpinner> waypoints_spinner_;
};

}  // namespace se3_interpolation
