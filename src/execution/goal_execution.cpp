#include "se3_interpolation/execution/goal_execution.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace se3_interpolation
{
namespace
{
/// "1.5e-05 m" etc.: the values of the messages, to 4 significant digits (what a user compares;
/// the tolerances are round numbers).
std::string withUnit(double value, const char* unit)
{
  char text[32];
  std::snprintf(text, sizeof(text), "%.4g", value);
  return std::string(text) + " " + unit;
}

/// What differs between the frame's state `shown` and the goal's first state `start`, beyond the
/// tolerances; "" when nothing does. With `at_rest`, the frame is held: its acceleration is not
/// compared (a goal may start accelerating from rest) and the pose takes the rest tolerances.
std::string stateDifference(const TrajectorySample& shown, const TrajectorySample& start, bool at_rest,
                            double linear_tolerance, double angular_tolerance)
{
  const PoseError e = poseError(shown.pose, start.pose);
  if (e.linear > linear_tolerance)
    return "its position is " + withUnit(e.linear, "m") + " from the frame's (tolerance " +
           withUnit(linear_tolerance, "m") + ")";
  if (e.angular > angular_tolerance)
    return "its orientation is " + withUnit(e.angular, "rad") + " from the frame's (tolerance " +
           withUnit(angular_tolerance, "rad") + ")";
  const double dv = (start.velocity.linear - shown.velocity.linear).norm();
  const double dw = (start.velocity.angular - shown.velocity.angular).norm();
  if (dv > kSpliceTolerance || dw > kSpliceTolerance)
    return "its velocity differs from the frame's by " + withUnit(dv, "m/s") + " and " + withUnit(dw, "rad/s") +
           (at_rest ? " (the frame is at rest)" : "");
  if (at_rest)
    return "";
  const double da = (start.acceleration.linear - shown.acceleration.linear).norm();
  const double dal = (start.acceleration.angular - shown.acceleration.angular).norm();
  if (da > kSpliceTolerance || dal > kSpliceTolerance)
    return "its acceleration differs from the frame's by " + withUnit(da, "m/s^2") + " and " + withUnit(dal, "rad/s^2");
  return "";
}
}  // namespace

PoseError poseError(const Pose<double>& desired, const Pose<double>& actual)
{
  PoseError e;
  e.linear = (actual.p - desired.p).norm();
  e.angular = rotationAngle(Quaternion<double>(desired.q.conjugate() * actual.q));
  return e;
}

GoalStart checkGoalStart(const GoalTrajectory& goal, Nanoseconds stamp, Nanoseconds now,
                         const std::function<std::optional<PlaybackState>(Nanoseconds)>& shown_at, double rest_linear,
                         double rest_angular)
{
  const Nanoseconds end = stamp + toNanoseconds(goal.endTime());
  if (end < now)
    throw InvalidGoalError(GoalError::kOldHeaderTimestamp,
                           "trajectory.header.stamp: the trajectory ended " + withUnit(secondsBetween(end, now), "s") +
                               " ago (its last point is at time_from_start " + formatNumber(goal.endTime()) + " s)");
  GoalStart start;
  start.instant = stamp + toNanoseconds(goal.startTime());
  start.time = goal.startTime();
  const bool late = start.instant < now;
  if (late)
  {
    start.instant = now;
    start.time = secondsBetween(stamp, now);
  }
  const std::optional<PlaybackState> shown = shown_at(start.instant);
  if (!shown)
    return start;  // nothing has played on the frame: the goal places it
  const bool at_rest = !shown->moving;
  const double linear = at_rest && rest_linear > 0.0 ? rest_linear : kSpliceTolerance;
  const double angular = at_rest && rest_angular > 0.0 ? rest_angular : kSpliceTolerance;
  const std::string difference = stateDifference(shown->sample, goal.stateAt(start.time), at_rest, linear, angular);
  if (difference.empty())
    return start;
  if (late)
    throw InvalidGoalError(GoalError::kOldHeaderTimestamp,
                           "trajectory.header.stamp: the trajectory started " +
                               withUnit(secondsBetween(stamp + toNanoseconds(goal.startTime()), now), "s") +
                               " ago and its point of now (time_from_start " + formatNumber(start.time) +
                               " s) is not the frame's state: " + difference);
  throw InvalidGoalError(GoalError::kInvalidGoal,
                         "trajectory.points[0]: the goal does not start at the frame's " +
                             std::string(at_rest ? "held pose" : "current motion") + ": " + difference +
                             (at_rest ? " (start it at the held pose, at rest)" :
                                        " (generate it with from_current, and send it before its stamp)"));
}

GoalSupervisor::GoalSupervisor(const GoalTolerances& tolerances, Nanoseconds end, const Pose<double>& last)
  : tolerances_(tolerances), end_(end), last_(last)
{
}

Nanoseconds measurementInstant(Nanoseconds stamp, Nanoseconds now)
{
  return std::min(now, std::max(stamp, now - toNanoseconds(kMaxMeasurementAge)));
}

GoalProgress GoalSupervisor::update(Nanoseconds now, const Pose<double>& desired,
                                    const std::optional<Pose<double>>& actual)
{
  error_ = actual ? poseError(desired, *actual) : PoseError();
  if (now < end_)
  {
    if (!actual)
      return GoalProgress::kRunning;
    if (tolerances_.path_linear > 0.0 && error_.linear > tolerances_.path_linear)
    {
      message_ = "path_tolerance_linear: the measured frame is " + withUnit(error_.linear, "m") +
                 " from the setpoint (tolerance " + withUnit(tolerances_.path_linear, "m") + ")";
      return GoalProgress::kPathToleranceViolated;
    }
    if (tolerances_.path_angular > 0.0 && error_.angular > tolerances_.path_angular)
    {
      message_ = "path_tolerance_angular: the measured frame is " + withUnit(error_.angular, "rad") +
                 " from the setpoint (tolerance " + withUnit(tolerances_.path_angular, "rad") + ")";
      return GoalProgress::kPathToleranceViolated;
    }
    return GoalProgress::kRunning;
  }
  const bool checked = tolerances_.goal_linear > 0.0 || tolerances_.goal_angular > 0.0;
  if (!checked)
    return GoalProgress::kSucceeded;
  std::string outside;
  if (!actual)
    outside = "the measured frame has not been seen";
  else
  {
    const PoseError to_goal = poseError(last_, *actual);
    if (tolerances_.goal_linear > 0.0 && to_goal.linear > tolerances_.goal_linear)
      outside = "goal_tolerance_linear: the measured frame is " + withUnit(to_goal.linear, "m") +
                " from the last point (tolerance " + withUnit(tolerances_.goal_linear, "m") + ")";
    else if (tolerances_.goal_angular > 0.0 && to_goal.angular > tolerances_.goal_angular)
      outside = "goal_tolerance_angular: the measured frame is " + withUnit(to_goal.angular, "rad") +
                " from the last point (tolerance " + withUnit(tolerances_.goal_angular, "rad") + ")";
  }
  if (outside.empty())
    return GoalProgress::kSucceeded;
  if (secondsBetween(end_, now) <= tolerances_.goal_time)
    return GoalProgress::kRunning;
  message_ = outside + ", " + withUnit(secondsBetween(end_, now), "s") + " after the end (goal_time_tolerance " +
             withUnit(tolerances_.goal_time, "s") + ")";
  return GoalProgress::kGoalToleranceViolated;
}

}  // namespace se3_interpolation
