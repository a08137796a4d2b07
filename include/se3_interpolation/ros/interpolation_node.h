// ros/ (not in the core library): conversions.h (toMsg/fromMsg between messages and core
// types), node_parameters.h (the node's parameters validated into a struct),
// interpolation_node.h (this header: the node class, also loaded as a nodelet).
//
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
// ~waypoints, ~clear_waypoints and dynamic_reconfigure's ~set_parameters run on the global queue
// (main spins it; under a nodelet manager, the nodelet's queue); the TF timer (with the /tf
// collision watch) and the master watchdog each have their own queue and thread. The run-time
// parameters are read and written under a mutex. The waypoint buffer and the latest
// trajectory are shared under mutexes; publishing a trajectory is serialised.
//
// /tf_static carries exactly the static frames of the latest published trajectory: the node
// latches its own tf2_msgs/TFMessage with the whole set, replacing the previous one
// (tf2_ros::StaticTransformBroadcaster would keep every frame it ever sent).
//
// Playback: the moving frame replays the latest trajectory once and holds its last pose
// (~loop false, the default) or replays it forever (~loop true). ~clear_waypoints empties the
// buffer, stops playback (the frame holds the pose it has at that moment), deletes the markers
// and publishes an empty ~path so that rviz clears it.
//
// TF collisions: the node watches /tf for its own moving frame sent by another publisher (two
// instances with the same ~child_frame_id, say) and warns, throttled, naming that publisher.
//
// Run-time parameters: a dynamic_reconfigure server (cfg/InterpolationNode.cfg, on ~) changes
// the request defaults and the playback settings (~loop, ~tf_rate); each change is validated as
// at start-up, a refused one is warned and its old value kept.
//
// Waypoints as TF frames: a request's waypoint_frames are looked up with tf2 in the waypoints'
// frame, each waiting up to ~tf_timeout, on the service thread that serves the request.
//
// Nodelet: InterpolationNodelet (src/ros/interpolation_nodelet.cpp) owns one InterpolationNode on
// the nodelet's handles; everything above holds there too.
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

#include <boost/thread/recursive_mutex.hpp>
#include <dynamic_reconfigure/server.h>
#include <tf2_msgs/TFMessage.h>

#include <atomic>
#include <map>
#include <memory>
#include <mutex>

#include "se3_interpolation/GenerateTrajectory.h"
#include "se3_interpolation/InterpolationNodeConfig.h"
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
    std::function<Pose<double>(double)> point_at;
    ros::Time stamp;  ///< trajectory time 0
    double start_time = 0.0;
    double duration = 0.0;
    std::string frame_id;
    std::string child_frame_id;
    std::function<TrajectorySample(double)> state_at;  ///< for replanning from the current motion
    /// The trajectory that plays until this one starts (a replan switches at stamp + start_time,
    /// ~replan_lead after the request): no jump on the moving frame while the new one is pending.
    std::shared_ptr<const Playback> previous;
  };

  bool generate(GenerateTrajectory::Request& req, GenerateTrajectory::Response& res);
  bool clearWaypoints(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  void waypointCallback(const ros::MessageEvent<const geometry_msgs::PoseStamped>& event);
  void waypointsCallback(const geometry_msgs::PoseArray::ConstPtr& msg);
  void tfTimerCallback(const ros::TimerEvent& event);
  void broadcastMovingFrame();

  // Replanning from the current motion (README "Replanning").
  /// The playback the moving frame shows at `time`: the latest, or the one it replaces while the
  /// latest has not started yet.
  std::shared_ptr<const Playback> playbackAt(const ros::Time& time) const;
  /// The trajectory time shown at `time` (looped or held at the ends); `ended` says whether it is
  /// held at the end (or before the start) rather than moving.
  double playbackClock(const Playback& playback, const ros::Time& time, bool* ended) const;
  /// Fills r->start_state with the moving frame's state at `switch_time` if `child` is playing
  /// (at rest at the held pose when its trajectory ended); leaves it empty when nothing plays.
  void startFromCurrent(const ros::Time& switch_time, const std::string& frame, const std::string& child,
                        TrajectoryRequest* r) const;
  void watchdogCallback(const ros::TimerEvent& event);
  /// Warns when a publisher's header.seq jumps (messages dropped by the queue).
  void noticeDrops(const std::string& publisher, std::uint32_t seq);

  /// Validates, generates and (if asked) publishes; fills `res` and never throws.
  void generateInto(const GenerateTrajectory::Request& req, GenerateTrajectory::Response& res);
  void publish(const TrajectoryResult& result, const GenerateTrajectory::Response& res, const std_msgs::Header& header,
               const std::string& child_frame_id);
  void autoGenerate();
  /// Fills the request's empty fields from the (run-time) defaults.
  void applyRequestDefaults(TrajectoryRequest* request) const;
  /// The poses of `frames` in `target`, looked up with tf2 (each waiting up to ~tf_timeout);
  /// throws InvalidInputError naming waypoint_frames[i] for an invalid or unknown frame.
  std::vector<geometry_msgs::Pose> lookUpWaypointFrames(const std::vector<std::string>& frames,
                                                        const std::string& target);
  /// dynamic_reconfigure: validates each changed field, keeps (and writes back) refused ones.
  void reconfigure(InterpolationNodeConfig& config, std::uint32_t level);
  InterpolationNodeConfig currentConfig() const;
  /// /tf: warns (throttled) when another publisher sends our moving frame.
  void tfWatchCallback(const ros::MessageEvent<const tf2_msgs::TFMessage>& event);
  /// Stops playback: the moving frame holds the pose it has now.
  void holdPlayback();
  /// ~status for one generation; `source` is "service" or "auto_generation".
  void publishStatus(const GenerateTrajectory::Request& req, const GenerateTrajectory::Response& res,
                     const std::string& source);

  ros::NodeHandle nh_;
  ros::NodeHandle private_nh_;
  NodeParameters params_;
  /// Guards the fields of params_ that dynamic_reconfigure changes (request defaults, loop, tf_rate).
  mutable std::mutex params_mutex_;
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<InterpolationNodeConfig>> reconfigure_server_;
  ros::Subscriber tf_watch_sub_;

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

  mutable std::mutex playback_mutex_;
  std::shared_ptr<const Playback> playback_;
  ros::Time last_tf_stamp_;
};

}  // namespace se3_interpolation
