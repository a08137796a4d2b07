// ros/ (not in the core library): the node is a thin composition of one-job parts, each in its
// own file: node_parameters.h (the parameter table, loading, validation), run_time_parameters.h
// (dynamic_reconfigure), waypoint_topics.h (the waypoint buffer's topics), moving_frame.h (TF
// output and the /tf collision watch), master_watchdog.h (surviving a master restart),
// conversions.h (toMsg/fromMsg), and, ROS-free, execution/playback.h (what the moving frame
// shows over time) and execution/waypoint_buffer.h. This header: the node class, also loaded as
// a nodelet (interpolation_nodelet.cpp).
//
// se3_interpolation_node: the ROS face of the planner. Service ~generate (GenerateTrajectory),
// waypoint buffer (~waypoint, ~waypoints, ~clear_waypoints), latched ~path / ~trajectory /
// ~markers, latched ~status (GenerationStatus after every generation, service call or
// auto-generation), and TF: the moving frame ~child_frame_id at ~tf_rate Hz plus static frames
// <child_frame_id>_<k> (docs/ros_interface.md).
//
// Threading: ~generate runs on its own callback queue served by ~service_threads threads, so a
// heavy request never delays a light one, the topics or TF; the waypoint topics, the TF timer and
// the master watchdog each have their own threads (see their headers); ~clear_waypoints and
// dynamic_reconfigure's ~set_parameters run on the global queue (main spins it; under a nodelet
// manager, the nodelet's queue). Publishing a trajectory is serialised.
//
// Playback: the moving frame replays the latest trajectory once and holds its last pose (~loop
// false, the default) or replays it forever (~loop true). A from_current request starts from the
// state the frame has at its switch time and is spliced there. Once a ~follow_trajectory goal has
// played, only goals move the frame (the setpoint ~command). ~clear_waypoints empties the buffer,
// brings the frame to rest along its path within the bounds (the stop of a cancel), deletes the
// markers and publishes an empty ~path so that rviz clears it.
//
// Waypoints as TF frames: a request's waypoint_frames are looked up with tf2 in the waypoints'
// frame, each waiting up to ~tf_timeout, on the service thread that serves the request.
//
// Memory: no copy of a published message is kept (roscpp keeps the latched one), the queues are
// bounded, large allocations are mapped on their own (a fixed M_MMAP_THRESHOLD, for the whole
// process) and once a second the node returns freed heap memory to the system (malloc_trim), so
// that its size returns after floods and large publications.
#pragma once

#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "se3_interpolation/GenerateTrajectory.h"
#include "se3_interpolation/execution/playback.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/ros/node_arm.h"
#include "se3_interpolation/ros/follow_trajectory_server.h"
#include "se3_interpolation/ros/master_watchdog.h"
#include "se3_interpolation/ros/moving_frame.h"
#include "se3_interpolation/ros/run_time_parameters.h"
#include "se3_interpolation/ros/waypoint_topics.h"

namespace se3_interpolation
{
class InterpolationNode
{
public:
  /// `nh` is the public handle, `private_nh` the private one (`~`).
  InterpolationNode(ros::NodeHandle nh, ros::NodeHandle private_nh);
  ~InterpolationNode();

private:
  bool generate(GenerateTrajectory::Request& req, GenerateTrajectory::Response& res);
  bool clearWaypoints(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  /// Validates, generates and (if asked) publishes; fills `res` and never throws.
  void generateInto(const GenerateTrajectory::Request& req, GenerateTrajectory::Response& res);
  /// A request's waypoints in their frame: the request's poses (in its header's frame, else
  /// ~frame_id) and its waypoint_frames looked up in that frame, or, when it gives neither, the
  /// ~waypoint buffer's poses with their stamps as a recording's times.
  struct Waypoints
  {
    std::vector<geometry_msgs::Pose> poses;
    std::string frame;
    std::vector<double> recorded_times;  ///< the buffered waypoints' stamps (empty for the request's)
  };
  Waypoints gatherWaypoints(const GenerateTrajectory::Request& req, const NodeParameters& params) const;
  /// The motion's stamp (the request's, ~replan_lead from now when it starts from the current
  /// motion, or zero) and its start: from the current motion (from_current, startFromCurrent), or
  /// a recording's own times (a fit of the buffer without times, moved out of *recorded_times).
  ros::Time startOf(const GenerateTrajectory::Request& req, const NodeParameters& params, const std::string& frame,
                    const std::string& child, std::vector<double>* recorded_times, TrajectoryRequest* r) const;
  /// Publishes the topics and plays the trajectory on the moving frame, unless goals own the frame
  /// (FollowTrajectoryServer::ownsFrame); returns whether it was played.
  bool publish(const TrajectoryResult& result, const nav_msgs::Path& path,
               const trajectory_msgs::MultiDOFJointTrajectory& trajectory, const std_msgs::Header& header,
               const std::string& child_frame_id, const NodeParameters& params);
  void autoGenerate();
  /// Fills the request's empty fields from the (run-time) defaults; returns the fields filled.
  static std::vector<std::string> applyRequestDefaults(const NodeParameters& params, TrajectoryRequest* request);
  /// `message` (the core's, starting with a request field) naming the node's parameter "~<field>"
  /// instead where the node filled that field from it.
  static std::string namingParameters(const std::string& message, const std::vector<std::string>& filled);
  /// The poses of `frames` in `target`, looked up with tf2 (each waiting up to ~tf_timeout);
  /// throws InvalidInputError naming waypoint_frames[i] for an invalid or unknown frame.
  std::vector<geometry_msgs::Pose> lookUpWaypointFrames(const std::vector<std::string>& frames,
                                                        const std::string& target, double timeout) const;
  /// Fills r->start_state with the moving frame's state at `switch_time` if `child` is playing
  /// (at rest at the held pose when its trajectory ended); leaves it empty when nothing plays.
  void startFromCurrent(const ros::Time& switch_time, const std::string& frame, const std::string& child,
                        TrajectoryRequest* r) const;
  /// ~status for one generation; `source` is "service" or "auto_generation".
  void publishStatus(const GenerateTrajectory::Request& req, const GenerateTrajectory::Response& res,
                     const std::string& source);
  /// Once a second: the waypoint topics' drop warning, and freed heap memory back to the system.
  void maintenanceCallback(const ros::WallTimerEvent& event);

  ros::NodeHandle nh_;
  ros::NodeHandle private_nh_;
  const NodeParameters start_params_;  ///< as loaded: the start-up-only ones stay so
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  Playback playback_;
  std::mutex publish_mutex_;  ///< one trajectory published at a time (topics, /tf_static, playback)

  ros::Publisher path_pub_;
  ros::Publisher trajectory_pub_;
  ros::Publisher markers_pub_;
  ros::Publisher status_pub_;
  std::unique_ptr<MovingFrame> moving_frame_;
  std::unique_ptr<NodeArm> arm_;  ///< the arm following the motions (~tip_link), or why it is not
  std::unique_ptr<WaypointTopics> waypoint_topics_;
  std::unique_ptr<RunTimeParameters> parameters_;
  std::unique_ptr<FollowTrajectoryServer> follow_server_;

  ros::ServiceServer clear_service_;
  ros::CallbackQueue service_queue_;
  ros::ServiceServer generate_service_;
  std::unique_ptr<ros::AsyncSpinner> service_spinner_;
  std::unique_ptr<MasterWatchdog> watchdog_;
  ros::CallbackQueue maintenance_queue_;
  ros::WallTimer maintenance_timer_;
  std::unique_ptr<ros::AsyncSpinner> maintenance_spinner_;
};

}  // namespace se3_interpolation
