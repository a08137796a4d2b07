// The supervision of an executed goal, without ROS: whether a goal may start from what the moving
// frame shows (its start rule), how far the measured frame is from the setpoint, and when a goal
// has succeeded or failed against its tolerances. ros/follow_trajectory_server.h is the action
// server that feeds these with ROS time, TF lookups and goal messages (docs/ros_interface.md,
// "Executing motions"). The model is joint_trajectory_controller's: the controller's logic is
// plain code over segments and tolerances; the ROS layer only connects it.
//
// Frames and units: world_T_body poses of the moving frame (the goal's child) in the trajectory's
// frame; spatial twists (ṗ, ω) with Ṙ = [ω]× R and their derivatives (p̈, ω̇); m, rad, s; instants
// on the playback clock (int64 ns, execution/playback.h).
//
// The start rule (a goal must not make the frame jump):
//  - while a motion plays on the frame at the goal's start instant, the goal's first state must
//    be the state the frame has there: pose, velocity and acceleration within kSpliceTolerance
//    (what ~generate with from_current returns), so that the goal replaces the motion C² there;
//  - at rest (held after a motion, a stop or a goal), the goal must start at the held pose within
//    the node's start tolerance (~start_tolerance_linear / ~start_tolerance_angular, a small fixed
//    distance, never a goal's own tolerance: a goal's path tolerance may be metres; kSpliceTolerance
//    where 0) with zero velocity;
//  - when nothing has played on the frame yet, any start is taken (the goal places the frame).
// A goal whose time zero (header.stamp) lies so far back that its start has passed starts at its
// point of `now` when that point meets the rule, else it is refused OLD_HEADER_TIMESTAMP; a goal
// that has wholly passed is refused so too.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "se3_interpolation/execution/goal_trajectory.h"
#include "se3_interpolation/execution/playback.h"

namespace se3_interpolation
{
/// A goal's first state must match the frame's to this (m, rad, m/s, rad/s, m/s², rad/s²): the
/// issue's 1e-6, far above the rounding of a from_current trajectory (its first sample is the
/// start state to ~1e-15) and far below any visible jump.
constexpr double kSpliceTolerance = 1e-6;

/// Tolerances of one goal, after the node's defaults filled its zeros (0 = not checked).
struct GoalTolerances
{
  double path_linear = 0.0;   ///< m
  double path_angular = 0.0;  ///< rad
  double goal_linear = 0.0;   ///< m
  double goal_angular = 0.0;  ///< rad
  double goal_time = 0.0;     ///< s after the motion's end for the measured frame to arrive
};

/// The distance between a setpoint and a measured pose.
struct PoseError
{
  double linear = 0.0;   ///< |p_actual − p_desired| (m)
  double angular = 0.0;  ///< the angle of R_desiredᵀ R_actual (rad, in [0, π])
};

/// The distance from `desired` to `actual` (q and −q are the same rotation).
PoseError poseError(const Pose<double>& desired, const Pose<double>& actual);

/// Where and when a goal starts.
struct GoalStart
{
  Nanoseconds instant = 0;  ///< when the goal takes over the frame
  double time = 0.0;        ///< the goal's time_from_start at that instant
};

/// The start of `goal` whose time zero is `stamp`, accepted at `now`. `shown_at` gives what the
/// frame shows at an instant (Playback::at; empty when nothing has played on the goal's frame): it
/// is asked for the start instant, which is known only here. `rest_linear` / `rest_angular` are the pose tolerances at rest (the
/// node's start tolerance; kSpliceTolerance where 0). Throws InvalidGoalError: kOldHeaderTimestamp
/// when the goal has ended before `now`, or started before it and its point of `now` does not
/// meet the start rule; kInvalidGoal when its start does not (the message says what differs, by
/// how much, and suggests from_current).
GoalStart checkGoalStart(const GoalTrajectory& goal, Nanoseconds stamp, Nanoseconds now,
                         const std::function<std::optional<PlaybackState>(Nanoseconds)>& shown_at, double rest_linear,
                         double rest_angular);

/// A measurement is compared with the setpoint of its own instant (its stamp), so that the
/// latency between the measuring and the check (a driver's publication, TF, the feedback timer)
/// is not counted as a deviation; one older than this (s) counts as taken this long ago, so that
/// a measured frame that stops arriving (a dead driver) still shows the setpoint moving away.
/// 0.2 s: ten periods of a 50 Hz TF broadcaster, beyond the latency of a working one.
constexpr double kMaxMeasurementAge = 0.2;

/// The instant whose setpoint a measurement stamped `stamp` is compared with at `now`: the
/// stamp, within [now − kMaxMeasurementAge, now] (a stamp ahead of `now`, a clock's skew, is now).
Nanoseconds measurementInstant(Nanoseconds stamp, Nanoseconds now);

/// How a running goal stands.
enum class GoalProgress
{
  kRunning,                ///< moving, or waiting for the measured frame after the end
  kSucceeded,              ///< ended, and the measured frame within the goal tolerance (or none)
  kPathToleranceViolated,  ///< the measured frame left the path tolerance while moving
  kGoalToleranceViolated   ///< not within the goal tolerance goal_time after the end
};

/// Follows one goal from its start to its end: fed at the feedback rate with the setpoint and the
/// measured pose, says when the goal succeeds or fails (joint_trajectory_controller's path and
/// goal constraints). Not thread-safe: one owner calls it.
class GoalSupervisor
{
public:
  /// `end` is the instant of the goal's last point, `last` its pose.
  GoalSupervisor(const GoalTolerances& tolerances, Nanoseconds end, const Pose<double>& last);

  /// The progress at `now` with setpoint `desired` and measured pose `actual` (empty when
  /// nothing is measured: then only time decides, and a goal tolerance cannot be confirmed).
  /// The error of the last update is in error(); message() says what failed.
  GoalProgress update(Nanoseconds now, const Pose<double>& desired, const std::optional<Pose<double>>& actual);

  /// The measured frame's distance from the setpoint at the last update (0 when not measured).
  const PoseError& error() const { return error_; }
  /// Why the goal failed, naming the tolerance and the values; "" while it has not.
  const std::string& message() const { return message_; }

private:
  GoalTolerances tolerances_;
  Nanoseconds end_;
  Pose<double> last_;
  PoseError error_;
  std::string message_;
};

}  // namespace se3_interpolation
