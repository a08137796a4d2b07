// se3_interpolation_node: the ROS face of the planner.
//
// Service ~generate (GenerateTrajectory), waypoint buffer (~waypoint, ~waypoints,
// ~clear_waypoints), latched ~path / ~trajectory / ~markers, latched ~status
// (GenerationStatus after every generation, service call or auto-generation), and TF: the moving frame
// ~child_frame_id at ~tf_rate Hz plus static frames <child_frame_id>_<k>.
//
// Threading: ~generate runs on its own callback queue served by ~service_threads threads,
// so a heavy request never delays a light one, the topics or TF. ~waypoint has its own queue
// and thread (its tf2 lookups wait up to ~tf_timeout each without blocking anything else);
// ~waypoints, ~clear_waypoints run on the global queue (main spins it); the TF timer and the
// master watchdog each have their own queue and thread. The waypoint buffer and the latest
// trajectory are shared under mutexes; publishing a trajectory is serialised.
//
// /tf_static carries exactly the static frames of the latest published trajectory: the node
// latches its own tf2_msgs/TFMessage with the whole set, replacing the previous one
// (tf2_ros::StaticTransformBroadcaster would keep every frame it ever sent).
//
// Master watchdog: every ~master_check_period s the node asks the master whether it still
// knows the ~generate service; after a master restart it does not (roscpp never re-registers), so the node
// logs why and shuts down with exit status 1, and the launch file's respawn starts it anew.
#pragma once

#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/PoseStamped.h>

#include <atomic>
#include <map>
#include <memory>
#include <mutex>

#include "se3_interpolation/GenerateTrajectory.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/ros/node_parameters.h"

namespace se3_interpolation
{
class InterpolationNode
{
public:
  /// `nh` is the public handle, `private_nh` the private one (`~`).
  InterpolationNode(ros::NodeHandle nh, ros::NodeHandle private_nh);
  ~InterpolationNode();

  /// The process exit status main() should return: 0, or 1 after the watchdog shut down.
  int exitStatus() const { return exit_status_; }

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
  void waypointCallback(const ros::MessageEvent<const geometry_msgs::PoseStamped>& event);
  void waypointsCallback(const geometry_msgs::PoseArray::ConstPtr& msg);
  void tfTimerCallback(const ros::TimerEvent& event);
  void broadcastMovingFrame();
  void watchdogCallback(const ros::TimerEvent& event);
  /// Warns when a publisher's header.seq jumps (messages dropped by the queue).
  void noticeDrops(const std::string& publisher, std::uint32_t seq);

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
  ros::Publisher tf_static_pub_;

  ros::CallbackQueue tf_queue_;
  std::unique_ptr<ros::AsyncSpinner> tf_spinner_;
  ros::Timer tf_timer_;
  ros::CallbackQueue service_queue_;
  std::unique_ptr<ros::AsyncSpinner> service_spinner_;
  ros::CallbackQueue waypoint_queue_;
  std::unique_ptr<ros::AsyncSpinner> waypoint_spinner_;
  ros::CallbackQueue watchdog_queue_;
  std::unique_ptr<ros::AsyncSpinner> watchdog_spinner_;
  ros::Timer watchdog_timer_;
  std::atomic<int> exit_status_{ 0 };

  std::mutex publish_mutex_;  ///< one trajectory published at a time (topics, /tf_static, playback)
  std::map<std::string, std::uint32_t> last_seq_;  ///< per ~waypoint publisher (waypoint thread only)
  std::uint64_t dropped_waypoints_ = 0;            ///< ~waypoint messages lost so far (waypoint thread only)

  std::mutex buffer_mutex_;
  std::vector<geometry_msgs::Pose> buffer_;
  std::string buffer_frame_;

  std::mutex playback_mutex_;
  std::shared_ptr<const Playback> playback_;
  ros::Time last_tf_stamp_;
};

}  // namespace se3_interpolation
