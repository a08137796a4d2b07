// se3_interpolation_node: the ROS face of the planner.
//
// Service ~generate (GenerateTrajectory), waypoint buffer (~waypoint, ~waypoints,
// ~clear_waypoints), latched ~path / ~trajectory / ~markers, latched ~status
// (GenerationStatus after every generation, service call or auto-generation), and TF: the moving frame
// ~child_frame_id at ~tf_rate Hz plus static frames <child_frame_id>_<k>.
//
// Threading: service and topic callbacks run on the global queue (main spins it); the
// TF timer has its own callback queue and spinner thread, so a long generation never
// starves the moving frame. The latest trajectory is shared under a mutex.
#pragma once

#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/PoseStamped.h>

#include <memory>
#include <mutex>

#include "se3_interpolation/GenerateTrajectory.h"
#include "se3_interpolation/planner.h"
#include "se3_interpolation/ros/node_parameters.h"

namespace se3_interpolation
{
class InterpolationNode
{
public:
  /// `nh` is the public handle, `private_nh` the private one (`~`).
  InterpolationNode(ros::NodeHandle nh, ros::NodeHandle private_nh);
  ~InterpolationNode();

private:
  /// What the TF timer replays: the latest published trajectory.
  struct Playback
  {
    std::function<Pose<double>(double)> pose_at;
    ros::Time stamp;  ///< trajectory time 0
    double start_time = 0.0;
    double duration = 0.0;
    std::string frame_id;
    std::string child_frame_id;
  };

  bool generate(GenerateTrajectory::Request& req, GenerateTrajectory::Response& res);
  bool clearWaypoints(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  void waypointCallback(const geometry_msgs::PoseStamped::ConstPtr& msg);
  void waypointsCallback(const geometry_msgs::PoseArray::ConstPtr& msg);
  void tfTimerCallback(const ros::TimerEvent& event);

  /// Validates, generates and (if asked) publishes; fills `res` and never throws.
  void generateInto(const GenerateTrajectory::Request& req, GenerateTrajectory::Response& res);
  void publish(const TrajectoryResult& result, const GenerateTrajectory::Response& res, const std_msgs::Header& header,
               const std::string& child_frame_id);
  void autoGenerate();
  /// ~status for one generation; `source` is "service" or "auto_generation".
  void publishStatus(const GenerateTrajectory::Request& req, const GenerateTrajectory::Response& res,
                     const std::string& source);

  ros::NodeHandle nh_;
  ros::NodeHandle private_nh_;
  NodeParameters params_;

  ros::ServiceServer generate_service_;
  ros::ServiceServer clear_service_;
  ros::Subscriber waypoint_sub_;
  ros::Subscriber waypoints_sub_;
  ros::Publisher path_pub_;
  ros::Publisher trajectory_pub_;
  ros::Publisher markers_pub_;
  ros::Publisher status_pub_;

  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  tf2_ros::StaticTransformBroadcaster static_broadcaster_;

  ros::CallbackQueue tf_queue_;
  std::unique_ptr<ros::AsyncSpinner> tf_spinner_;
  ros::Timer tf_timer_;

  std::mutex buffer_mutex_;
  std::vector<geometry_msgs::Pose> buffer_;
  std::string buffer_frame_;

  std::mutex playback_mutex_;
  std::shared_ptr<const Playback> playback_;
  ros::Time last_tf_stamp_;
};

}  // namespace se3_interpolation
