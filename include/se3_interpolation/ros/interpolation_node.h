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
// so a heavy request never delays a light one, the topics or TF. ~waypoint and ~waypoints are
// taken off roscpp's queues at once by an intake thread each into bounded backlogs
// (MessageBacklog), each handled by its own worker thread (a ~waypoint's tf2 lookup waits up to
// ~tf_timeout without blocking anything else); ~clear_waypoints and dynamic_reconfigure's
// ~set_parameters run on the global queue (main spins it; under a nodelet manager, the nodelet's
// queue); the TF timer (with the /tf collision watch) and the master watchdog each have their
// own queue and thread. The run-time
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
// Dropped waypoint messages: every message of ~waypoint and ~waypoints that the node did not
// handle is counted: those its backlog (~waypoint_queue_size, 10 for ~waypoints) dropped to make
// room, and those lost before it (a gap in a publisher's header.seq). The counts are warned at
// most once a second and carried by every ~status.
//
// Memory: no copy of a published message is kept (roscpp keeps the latched one), the queues are
// bounded, large allocations are mapped on their own (a fixed M_MMAP_THRESHOLD, for the whole
// process) and once a second the node returns freed heap memory to the system (malloc_trim),
// so that its size returns after floods and large publications.
//
// Master restart: every ~master_check_period s the node asks the master whether it still knows
// the ~generate service (and whether its /run_id changed). After a master restart it does not:
// roscpp never registers again by itself, so the node does, and keeps running: it writes its
// parameters in effect (the launch file's and later dynamic_reconfigure changes) back under its
// private namespace, registers every publication and subscription of its process (including
// tf2's, dynamic_reconfigure's and /rosout) and its services again, and connects its
// subscriptions to the publishers the new master knows. Playback, the waypoint buffer, the
// frames and the latched messages are untouched: a playing motion continues without a jump.
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
#include <string>
#include <vector>

#include "se3_interpolation/GenerateTrajectory.h"
#include "se3_interpolation/InterpolationNodeConfig.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/ros/message_backlog.h"
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
  /// Intake (roscpp's callbacks): count a header.seq gap, queue the message in its backlog.
  void waypointIntake(const ros::MessageEvent<const geometry_msgs::PoseStamped>& event);
  void waypointsIntake(const ros::MessageEvent<const geometry_msgs::PoseArray>& event);
  /// The backlogs' handlers (their worker threads).
  void waypointCallback(const geometry_msgs::PoseStamped::ConstPtr& msg);
  void waypointsCallback(const geometry_msgs::PoseArray::ConstPtr& msg);
  void tfTimerCallback(const ros::TimerEvent& event);
  void broadcastMovingFrame();

  // Replanning from the current motion (docs/timing.md, "Start states and replanning").
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
  /// Whether the reachable master has forgotten this node: it does not know ~generate, or its
  /// /run_id differs from the one seen at start-up.
  bool masterForgotUs();
  /// Registers everything again on a new master (see the header comment); returns a summary.
  std::string registerAgain();
  /// Once a second: warns about waypoint messages dropped since the last report, and returns
  /// freed heap memory to the system.
  void maintenanceCallback(const ros::WallTimerEvent& event);
  /// Messages a publisher's header.seq skipped since its previous one (0 for the first, for a
  /// restart and for publishers that do not number their messages); intake thread only.
  std::uint64_t seqGap(std::map<std::string, std::uint32_t>* last_seq, const std::string& publisher,
                       std::uint32_t seq);

  /// Validates, generates and (if asked) publishes; fills `res` and never throws.
  void generateInto(const GenerateTrajectory::Request& req, GenerateTrajectory::Response& res);
  void publish(const TrajectoryResult& result, const nav_msgs::Path& path,
               const trajectory_msgs::MultiDOFJointTrajectory& trajectory, const std_msgs::Header& header,
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
  /// Dropped messages so far: ~waypoint's and ~waypoints' (backlog drops and header.seq gaps).
  std::uint64_t droppedWaypointMessages() const;
  std::uint64_t droppedWaypointsMessages() const;
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
  std::vector<std::string> services_;  ///< resolved names of the services registered again
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
  ros::CallbackQueue intake_queue_;
  std::unique_ptr<ros::AsyncSpinner> intake_spinner_;
  ros::CallbackQueue array_intake_queue_;  ///< ~waypoints' intake (intake_queue_: ~waypoint's)
  std::unique_ptr<ros::AsyncSpinner> array_intake_spinner_;
  std::unique_ptr<MessageBacklog<geometry_msgs::PoseStamped::ConstPtr>> waypoint_backlog_;
  std::unique_ptr<MessageBacklog<geometry_msgs::PoseArray::ConstPtr>> waypoints_backlog_;
  ros::CallbackQueue watchdog_queue_;
  std::unique_ptr<ros::AsyncSpinner> watchdog_spinner_;
  ros::Timer watchdog_timer_;
  ros::WallTimer maintenance_timer_;
  std::string run_id_;  ///< the master's /run_id at start-up ("" when it has none)

  std::mutex publish_mutex_;  ///< one trajectory published at a time (topics, /tf_static, playback)
  /// Per publisher, the latest header.seq of ~waypoint and of ~waypoints (their intake threads).
  std::map<std::string, std::uint32_t> waypoint_seq_;
  std::map<std::string, std::uint32_t> waypoints_seq_;
  /// Messages lost before the backlogs (header.seq gaps), per topic.
  std::atomic<std::uint64_t> waypoint_gaps_{ 0 };
  std::atomic<std::uint64_t> waypoints_gaps_{ 0 };
  /// The totals of the latest drop warning (maintenance thread only).
  std::uint64_t reported_waypoint_drops_ = 0;
  std::uint64_t reported_waypoints_drops_ = 0;

  std::mutex buffer_mutex_;
  std::vector<geometry_msgs::Pose> buffer_;
  std::string buffer_frame_;

  mutable std::mutex playback_mutex_;
  std::shared_ptr<const Playback> playback_;
  ros::Time last_tf_stamp_;
};

}  // namespace se3_interpolation
