#include "se3_interpolation/ros/moving_frame.h"

#include <ros/this_node.h>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/ros/conversions.h"

namespace se3_interpolation
{
namespace
{
/// tf2 ignores one leading '/' in frame ids: so does the collision check.
std::string withoutLeadingSlash(const std::string& frame)
{
  return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame;
}
}  // namespace

MovingFrame::MovingFrame(ros::NodeHandle nh, ros::NodeHandle private_nh, const Playback& playback, bool publish_tf,
                         double rate, std::string child_frame_id)
  : playback_(playback), publish_tf_(publish_tf), default_child_(std::move(child_frame_id))
{
  static_pub_ = nh.advertise<tf2_msgs::TFMessage>("/tf_static", 1, true);
  ros::NodeHandle tf_nh(private_nh);
  tf_nh.setCallbackQueue(&queue_);
  timer_ = tf_nh.createTimer(ros::Duration(1.0 / rate), &MovingFrame::timerCallback, this);
  if (publish_tf_)
    watch_sub_ = tf_nh.subscribe("/tf", 100, &MovingFrame::watchCallback, this);
  spinner_ = std::make_unique<ros::AsyncSpinner>(1, &queue_);
  spinner_->start();
}

MovingFrame::~MovingFrame()
{
  spinner_->stop();
}

void MovingFrame::setRate(double rate)
{
  timer_.setPeriod(ros::Duration(1.0 / rate));
}

void MovingFrame::timerCallback(const ros::TimerEvent& /*event*/)
{
  // Nothing may leave a timer callback: roscpp would terminate the process.
  try
  {
    broadcast();
  }
  catch (const std::exception& e)
  {
    ROS_ERROR_STREAM_THROTTLE(10.0, "moving frame not broadcast: " << boundedMessage(e.what()));
  }
  catch (...)
  {
    ROS_ERROR_THROTTLE(10.0, "moving frame not broadcast: unexpected error");
  }
}

void MovingFrame::broadcast()
{
  if (!publish_tf_)
    return;
  const ros::Time now = ros::Time::now();
  if (now <= last_stamp_)
    return;
  const std::optional<PlaybackState> shown = playback_.at(static_cast<Nanoseconds>(now.toNSec()));
  if (!shown)
    return;
  geometry_msgs::TransformStamped ts;
  ts.header.stamp = now;
  ts.header.frame_id = shown->frame_id;
  ts.child_frame_id = shown->child_frame_id;
  toMsg(shown->sample.pose, ts.transform);
  broadcaster_.sendTransform(ts);
  last_stamp_ = now;
}

void MovingFrame::publishSamples(const TrajectoryResult& result, const std_msgs::Header& header,
                                 const std::string& child_frame_id, int samples)
{
  if (!publish_tf_ || samples <= 0)
    return;
  // The whole set, replacing the latched one: /tf_static holds this trajectory's frames only.
  tf2_msgs::TFMessage frames;
  for (int k = 0; k < samples; ++k)
  {
    const double t = result.start_time + (samples == 1 ? 0.0 : result.duration * k / (samples - 1));
    geometry_msgs::TransformStamped ts;
    ts.header = header;
    ts.child_frame_id = child_frame_id + "_" + std::to_string(k);
    toMsg(result.point_at(t), ts.transform);
    frames.transforms.push_back(ts);
  }
  static_pub_.publish(frames);
}

void MovingFrame::watchCallback(const ros::MessageEvent<const tf2_msgs::TFMessage>& event)
{
  const std::string& publisher = event.getPublisherName();  // the connection header's callerid
  if (publisher == ros::this_node::getName())
    return;  // our own broadcasts (also under a nodelet manager: its name is ours)
  const std::optional<PlaybackState> shown = playback_.at(static_cast<Nanoseconds>(ros::Time::now().toNSec()));
  // const: a non-const std::string would pick std::quoted by argument-dependent lookup.
  const std::string child = shown ? shown->child_frame_id : default_child_;
  for (const auto& t : event.getMessage()->transforms)
  {
    if (withoutLeadingSlash(t.child_frame_id) != child)
      continue;
    // Throttled: a colliding publisher at 50 Hz must not become 50 log lines a second.
    ROS_WARN_STREAM_THROTTLE(5.0, "TF collision: " << quotedText(publisher)
                                                   << " also publishes this node's moving frame " << quotedText(child)
                                                   << " (parent " << quotedText(t.header.frame_id)
                                                   << ") on /tf; give each instance its own ~child_frame_id "
                                                      "(launch argument child_frame_id)");
    return;
  }
}

}  // namespace se3_interpolation
