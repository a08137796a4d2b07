// ros/follow_trajectory_server.h: the action ~follow_trajectory (se3_interpolation/FollowTrajectory,
// actionlib::ActionServer) and the controller setpoint ~command. It makes the node the executor of
// a MultiDOFJointTrajectory: a goal is checked (execution/goal_trajectory.h: its points, its
// motion between them, the node's ~max_* bounds, at rest at its end; then its joint, frame and
// stamp; then execution/goal_execution.h's start rule), played on the node's one Playback (the
// moving TF frame ~child_frame_id, what from_current replans from) and supervised at
// ~feedback_rate against the measured frame ~actual_frame (execution/goal_execution.h's
// GoalSupervisor). A cancel or a path tolerance abort brings the frame to rest along its path
// (Playback::stop, within ~max_linear_acceleration / ~max_angular_acceleration, else in
// ~stop_time). docs/ros_interface.md, "Executing motions", is the user's description.
//
// ~command (geometry_msgs/PoseStamped, world_T_body of the moving frame in the trajectory's frame,
// the target convention of Cartesian controllers such as cartesian_motion_controller) carries the
// setpoint at ~command_rate from the first goal on: a goal's motion, its stop, or the pose held
// after it. Once a goal has played, ~generate publications (publish, auto-generation) no longer
// move the frame (ownsFrame), so ~command and the frame never part and never step.
//
// Threading: goals, cancels and the feedback timer run on one callback queue and thread (so a goal
// is checked and started in order), ~command on another (a long goal check never delays the
// setpoint). Starting a goal takes the node's publication mutex, so that no ~generate publication
// slips between its start check and its play.
#pragma once

#include <actionlib/server/action_server.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "se3_interpolation/FollowTrajectoryAction.h"
#include "se3_interpolation/execution/goal_execution.h"
#include "se3_interpolation/execution/playback.h"
#include "se3_interpolation/ros/node_parameters.h"

namespace se3_interpolation
{
/// The stop of a cancel, an abort or ~clear_waypoints: the node's ~max_*_acceleration and
/// ~max_*_jerk, and ~stop_time where none is set (execution/stop_law.h).
StopLimits stopLimitsOf(const NodeParameters& params);

/// How far ahead of the present a stop starts (s): the stop law is computed from a snapshot while
/// the motion plays on (milliseconds; execution/stop_law.h bounds its search), and must be in place
/// before it starts, or the frame would jump from the motion to the law. 50 ms: well above that
/// computation on a loaded machine, well below what a user notices in a cancel.
constexpr double kStopLead = 0.05;

/// The instant a stop asked for at `now` starts: now + kStopLead.
Nanoseconds stopStart(Nanoseconds now);

/// The tags of what the playback shows (Motion::tag): goals' start with this, so ~command knows them.
constexpr const char* kGoalTagPrefix = "follow_trajectory goal ";

class FollowTrajectoryServer
{
public:
  using ActionServer = actionlib::ActionServer<FollowTrajectoryAction>;
  using GoalHandle = ActionServer::GoalHandle;

  /// Serves ~follow_trajectory and ~command on `private_nh`. `playback` is the node's (shared with
  /// ~generate and TF), `tf` its buffer (for ~actual_frame and frame checks), `parameters` gives the
  /// parameters in effect, `publish_mutex` serialises every change of the playback.
  FollowTrajectoryServer(const ros::NodeHandle& private_nh, Playback& playback, const tf2_ros::Buffer& tf,
                         std::function<NodeParameters()> parameters, std::mutex& publish_mutex,
                         const NodeParameters& initial);
  ~FollowTrajectoryServer();

  /// The rates of ~command and of the feedback (Hz, > 0).
  void setRates(double command_rate, double feedback_rate);

  /// Something other than a goal took the moving frame (a ~generate publication, ~clear_waypoints):
  /// the running goal ends PREEMPTED, `why` in its error_string. Call with the publication mutex held.
  void interrupt(const std::string& why);

  /// Whether a goal has played on the moving frame: from then on the frame is the setpoint
  /// ~command carries, and nothing but goals may move it (a ~generate publication would make the
  /// frame and ~command part, and the next goal jump).
  bool ownsFrame() const { return owns_frame_; }

private:
  /// A running goal.
  struct Active
  {
    GoalHandle handle;
    std::string tag;        ///< its Motion::tag
    std::string frame_id;   ///< the trajectory's frame
    Nanoseconds stamp = 0;  ///< its time zero
    Pose<double> last;      ///< its last point
    GoalSupervisor supervisor;
  };

  void onGoal(GoalHandle handle);
  void onCancel(GoalHandle handle);
  void feedbackCallback(const ros::TimerEvent& event);
  void commandCallback(const ros::TimerEvent& event);
  /// Starts `handle` or rejects it with its code and message (never throws).
  void start(GoalHandle handle);
  /// Holds the frame where ~executed_frame (ros/frame_memory.h) says a previous instance left it
  /// at rest; marks the state unknown when it left it moving.
  void restoreFrame(const NodeParameters& params);
  /// Writes ~executed_frame when the frame executing goals starts moving or comes to rest (feedback
  /// thread).
  void rememberShownFrame(Nanoseconds now);
  /// With the state unknown (restoreFrame): holds the frame at ~actual_frame's measured pose, or
  /// refuses the goal (InvalidGoalError) when it is not measured.
  void placeFromMeasurement(const std::string& frame, const std::string& child, Nanoseconds now,
                            const NodeParameters& params);
  /// Brings the frame to rest from `now` and returns where it stops.
  Pose<double> stopFrame(Nanoseconds now, const NodeParameters& params);
  /// A pose of ~actual_frame and the instant it was measured at (its TF stamp).
  struct Measurement
  {
    Pose<double> pose;
    Nanoseconds stamp = 0;
  };
  /// The latest measurement of ~actual_frame in `frame` (empty when ~actual_frame is empty or
  /// unknown).
  std::optional<Measurement> measured(const std::string& frame, const NodeParameters& params) const;

  Playback& playback_;
  const tf2_ros::Buffer& tf_;
  std::function<NodeParameters()> parameters_;
  std::mutex& publish_mutex_;

  std::mutex mutex_;  ///< guards active_ and next_goal_
  std::optional<Active> active_;
  std::uint64_t next_goal_ = 1;
  std::atomic<bool> owns_frame_{ false };
  ros::NodeHandle private_nh_;
  /// A previous instance died while a goal moved the frame (ros/frame_memory.h); action thread.
  bool state_unknown_ = false;
  /// Whether ~executed_frame says at rest, as last written (feedback thread).
  std::optional<bool> remembered_rest_;

  ros::CallbackQueue action_queue_;
  ros::CallbackQueue command_queue_;
  ros::Publisher command_pub_;
  std::unique_ptr<ActionServer> server_;
  ros::Timer feedback_timer_;
  ros::Timer command_timer_;
  std::unique_ptr<ros::AsyncSpinner> action_spinner_;
  std::unique_ptr<ros::AsyncSpinner> command_spinner_;
};

}  // namespace se3_interpolation
