// ros/moving_frame.h: the node's TF output. The moving frame shows the playback (ROS-free,
// execution/playback.h) at ~tf_rate Hz on /tf, on its own callback queue and thread; /tf_static
// carries exactly the sampled frames <child_frame_id>_<k> of the latest published trajectory (the
// node latches its own tf2_msgs/TFMessage with the whole set, replacing the previous one:
// tf2_ros::StaticTransformBroadcaster would keep every frame it ever sent); and /tf is watched for
// the node's moving frame sent by another publisher (two instances with the same
// ~child_frame_id), warned about (throttled) naming that publisher.
#pragma once

#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_msgs/Header.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/transform_broadcaster.h>

#include <memory>
#include <string>

#include "se3_interpolation/execution/playback.h"
#include "se3_interpolation/planner/planner.h"

namespace se3_interpolation
{
class MovingFrame
{
public:
  /// Broadcasts `playback` at `rate` Hz (when `publish_tf`); `child_frame_id` is the frame the
  /// /tf watch looks for until a trajectory names another.
  MovingFrame(ros::NodeHandle nh, ros::NodeHandle private_nh, const Playback& playback, bool publish_tf, double rate,
              std::string child_frame_id);
  ~MovingFrame();

  /// The broadcast rate (Hz, > 0).
  void setRate(double rate);

  /// Replaces /tf_static's frames by `samples` evenly spaced poses of `result` (none: no message).
  void publishSamples(const TrajectoryResult& result, const std_msgs::Header& header, const std::string& child_frame_id,
                      int samples);

private:
  void timerCallback(const ros::TimerEvent& event);
  void broadcast();
  void watchCallback(const ros::MessageEvent<const tf2_msgs::TFMessage>& event);

  const Playback& playback_;
  const bool publish_tf_;
  const std::string default_child_;
  tf2_ros::TransformBroadcaster broadcaster_;
  ros::Publisher static_pub_;
  ros::CallbackQueue queue_;
  ros::Timer timer_;
  ros::Subscriber watch_sub_;
  std::unique_ptr<ros::AsyncSpinner> spinner_;
  ros::Time last_stamp_;  ///< TF stamps never repeat or go backwards (timer thread only)
};

}  // namespace se3_interpolation
