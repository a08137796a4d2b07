#include "se3_interpolation/ros/follow_trajectory_server.h"

#include <geometry_msgs/PoseStamped.h>

#include <utility>
#include <vector>

#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/ros/conversions.h"
#include "se3_interpolation/ros/frame_memory.h"

namespace se3_interpolation
{
namespace
{
Nanoseconds nanosecondsOf(const ros::Time& t)
{
  return static_cast<Nanoseconds>(t.toNSec());
}

/// A goal's tolerances, its zeros taken from the node's parameters.
GoalTolerances tolerancesOf(const FollowTrajectoryGoal& goal, const NodeParameters& p)
{
  auto either = [](double given, double fallback) { return given > 0.0 ? given : fallback; };
  GoalTolerances t;
  t.path_linear = either(goal.path_tolerance_linear, p.path_tolerance_linear);
  t.path_angular = either(goal.path_tolerance_angular, p.path_tolerance_angular);
  t.goal_linear = either(goal.goal_tolerance_linear, p.goal_tolerance_linear);
  t.goal_angular = either(goal.goal_tolerance_angular, p.goal_tolerance_angular);
  t.goal_time = either(goal.goal_time_tolerance, p.goal_time_tolerance);
  return t;
}

/// Refuses a negative or non-finite tolerance, naming it.
void requireTolerance(double value, const char* field)
{
  if (!(value >= 0.0) || !std::isfinite(value))
    throw InvalidGoalError(GoalError::kInvalidGoal, std::string(field) + ": " + formatNumber(value) +
                                                        " is not a finite tolerance >= 0 (0 = the node's default)");
}

/// The frame held at `pose`, at rest, tagged `tag`.
Motion heldMotion(const std::string& frame, const std::string& child, const Pose<double>& pose, const std::string& tag)
{
  TrajectorySample held;
  held.pose = pose;
  Motion m;
  m.state_at = [held](double) { return held; };
  m.frame_id = frame;
  m.child_frame_id = child;
  m.tag = tag;
  return m;
}

/// The node's ~geometry (validated by the parameter table, so always a known name).
GeometryType geometryOf(const NodeParameters& p)
{
  return parseName(p.geometry, "~geometry", RequestDefaults::kGeometry);
}
/// The goal's motion, checked in the order of docs/ros_interface.md ("How a goal ends"): its points,
/// its tolerances, rest at its end and the node's bounds, then its joints, then its frame (`frame`:
/// header.frame_id, else ~frame_id).
/// @throws InvalidGoalError naming the field, or the core's std::invalid_argument
GoalTrajectory checkedTrajectory(const FollowTrajectoryGoal& goal, const NodeParameters& params, std::string* frame)
{
  const auto& points = goal.trajectory.points;
  if (points.empty())
    throw InvalidGoalError(GoalError::kInvalidGoal, "trajectory.points: empty (give at least one point)");
  if (points.size() > static_cast<std::size_t>(params.max_waypoints))
    throw InvalidGoalError(GoalError::kInvalidGoal, "trajectory.points: " + std::to_string(points.size()) +
                                                        " points; the limit (~max_waypoints) is " +
                                                        std::to_string(params.max_waypoints));
  const double work = static_cast<double>(points.size()) * kGoalCheckSecondsPerPoint;
  if (work > params.max_work_seconds)
    throw InvalidGoalError(GoalError::kInvalidGoal, "trajectory.points: " + std::to_string(points.size()) +
                                                        " points take about " + formatNumber(work) +
                                                        " s to check; the limit (~max_work_seconds) is " +
                                                        formatNumber(params.max_work_seconds) + " s");
  std::vector<GoalPoint> goal_points;
  goal_points.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    if (points[i].transforms.empty())
      throw InvalidGoalError(GoalError::kInvalidJoints, indexedField("trajectory.points", i) +
                                                            ".transforms: empty (one per point, for joint " +
                                                            quotedText(params.child_frame_id) + ")");
    goal_points.push_back(fromMsg(points[i]));
  }
  requireTolerance(goal.path_tolerance_linear, "path_tolerance_linear");
  requireTolerance(goal.path_tolerance_angular, "path_tolerance_angular");
  requireTolerance(goal.goal_tolerance_linear, "goal_tolerance_linear");
  requireTolerance(goal.goal_tolerance_angular, "goal_tolerance_angular");
  requireTolerance(goal.goal_time_tolerance, "goal_time_tolerance");
  GoalTrajectory trajectory(std::move(goal_points), geometryOf(params));
  trajectory.requireEndsAtRest();
  trajectory.checkLimits(motionLimitsOf(params), kGoalLimitTolerance);

  const auto& names = goal.trajectory.joint_names;
  if (names.size() != 1)
    throw InvalidGoalError(GoalError::kInvalidJoints,
                           "trajectory.joint_names: " + std::to_string(names.size()) +
                               " given; one is executed, the node's moving frame ~child_frame_id " +
                               quotedText(params.child_frame_id));
  if (names[0] != params.child_frame_id)
    throw InvalidGoalError(GoalError::kInvalidJoints, "trajectory.joint_names[0]: " + quotedText(names[0]) +
                                                          " is not this node's moving frame ~child_frame_id " +
                                                          quotedText(params.child_frame_id));
  for (std::size_t i = 0; i < points.size(); ++i)
    if (points[i].transforms.size() > 1 || points[i].velocities.size() > 1 || points[i].accelerations.size() > 1)
      throw InvalidGoalError(GoalError::kInvalidJoints,
                             indexedField("trajectory.points", i) + ": " + std::to_string(points[i].transforms.size()) +
                                 " transforms, " + std::to_string(points[i].velocities.size()) + " velocities, " +
                                 std::to_string(points[i].accelerations.size()) +
                                 " accelerations for one joint (at most one each)");

  *frame = goal.trajectory.header.frame_id.empty() ? params.frame_id : goal.trajectory.header.frame_id;
  try
  {
    validateFrameId(*frame, "trajectory.header.frame_id");
  }
  catch (const InvalidInputError& e)
  {
    throw InvalidGoalError(GoalError::kInvalidGoal, e.what());
  }
  return trajectory;
}
}  // namespace

FollowTrajectoryServer::FollowTrajectoryServer(const ros::NodeHandle& private_nh, Playback& playback,
                                               const tf2_ros::Buffer& tf, std::function<NodeParameters()> parameters,
                                               std::mutex& publish_mutex, const NodeParameters& initial)
  : playback_(playback)
  , tf_(tf)
  , parameters_(std::move(parameters))
  , publish_mutex_(publish_mutex)
  , private_nh_(private_nh)
{
  restoreFrame(initial);
  ros::NodeHandle action_nh(private_nh);
  action_nh.setCallbackQueue(&action_queue_);
  ros::NodeHandle command_nh(private_nh);
  command_nh.setCallbackQueue(&command_queue_);
  command_pub_ = command_nh.advertise<geometry_msgs::PoseStamped>("command", 10);
  server_ = std::make_unique<ActionServer>(
      action_nh, "follow_trajectory", [this](GoalHandle h) { onGoal(std::move(h)); },
      [this](GoalHandle h) { onCancel(std::move(h)); }, false);
  feedback_timer_ = action_nh.createTimer(ros::Duration(1.0 / initial.feedback_rate),
                                          &FollowTrajectoryServer::feedbackCallback, this);
  command_timer_ =
      command_nh.createTimer(ros::Duration(1.0 / initial.command_rate), &FollowTrajectoryServer::commandCallback, this);
  server_->start();
  action_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &action_queue_);
  action_spinner_->start();
  command_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &command_queue_);
  command_spinner_->start();
}

FollowTrajectoryServer::~FollowTrajectoryServer()
{
  command_spinner_->stop();
  action_spinner_->stop();
  feedback_timer_.stop();
  command_timer_.stop();
  std::lock_guard<std::mutex> lock(mutex_);
  if (active_)
  {
    FollowTrajectoryResult result;
    result.error_string = "the node is shutting down";
    active_->handle.setAborted(result, result.error_string);
    active_.reset();
  }
}

void FollowTrajectoryServer::restoreFrame(const NodeParameters& params)
{
  const std::optional<RememberedFrame> remembered = recallFrame(private_nh_);
  if (!remembered)
    return;
  if (!remembered->at_rest)
  {
    state_unknown_ = true;
    ROS_WARN_STREAM("~follow_trajectory: this node restarted while a goal moved the frame (~"
                    << kFrameMemoryParameter << "): goals are refused until ~actual_frame is measured or a "
                    << "~generate publication places the frame");
    return;
  }
  const Nanoseconds now = nanosecondsOf(ros::Time::now());
  playback_.play(heldMotion(remembered->frame_id, params.child_frame_id, remembered->pose,
                            kGoalTagPrefix + std::string("0")),
                 now, now);
  owns_frame_ = true;
  remembered_rest_ = true;
  ROS_INFO_STREAM("~follow_trajectory: the frame is held where the previous instance left it (~"
                  << kFrameMemoryParameter << ")");
}

void FollowTrajectoryServer::rememberShownFrame(Nanoseconds now)
{
  if (!owns_frame_)
    return;
  const std::optional<PlaybackState> shown = playback_.at(now);
  if (!shown || (remembered_rest_ && *remembered_rest_ == !shown->moving))
    return;
  remembered_rest_ = !shown->moving;
  rememberFrame(private_nh_, RememberedFrame{ shown->frame_id, shown->sample.pose, !shown->moving });
}

void FollowTrajectoryServer::placeFromMeasurement(const std::string& frame, const std::string& child, Nanoseconds now,
                                                  const NodeParameters& params)
{
  const std::optional<Measurement> m = measured(frame, params);
  if (!m)
    throw InvalidGoalError(GoalError::kInvalidGoal,
                           "trajectory.points[0]: this node restarted while a goal moved the frame (~" +
                               std::string(kFrameMemoryParameter) +
                               "), so where the setpoint stood is unknown: set ~actual_frame to the measured frame "
                               "(the frame is then held at its pose), or place the frame with a ~generate "
                               "publication (publish: true)");
  playback_.play(heldMotion(frame, child, m->pose, kGoalTagPrefix + std::string("0")), now, now);
  state_unknown_ = false;
}

void FollowTrajectoryServer::setRates(double command_rate, double feedback_rate)
{
  command_timer_.setPeriod(ros::Duration(1.0 / command_rate));
  feedback_timer_.setPeriod(ros::Duration(1.0 / feedback_rate));
}

void FollowTrajectoryServer::interrupt(const std::string& why)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!active_)
    return;
  FollowTrajectoryResult result;
  result.error_code = FollowTrajectoryResult::SUCCESSFUL;
  result.error_string = why;
  active_->handle.setCanceled(result, why);
  active_.reset();
}

void FollowTrajectoryServer::onGoal(GoalHandle handle)
{
  try
  {
    start(std::move(handle));
  }
  catch (const std::exception& e)
  {
    ROS_ERROR_STREAM("~follow_trajectory: " << boundedMessage(e.what()));
  }
}

void FollowTrajectoryServer::start(GoalHandle handle)
{
  const FollowTrajectoryGoal& goal = *handle.getGoal();
  const NodeParameters params = parameters_();
  FollowTrajectoryResult result;
  try
  {
    std::string frame;
    const GoalTrajectory trajectory = checkedTrajectory(goal, params, &frame);
    const Nanoseconds now = nanosecondsOf(ros::Time::now());
    const Nanoseconds stamp = goal.trajectory.header.stamp.isZero() ? now : nanosecondsOf(goal.trajectory.header.stamp);
    const GoalTolerances tolerances = tolerancesOf(goal, params);
    const std::string child = params.child_frame_id;

    std::lock_guard<std::mutex> publishing(publish_mutex_);
    const std::optional<PlaybackState> shown_now = playback_.at(now);
    const bool plays_here = shown_now && shown_now->child_frame_id == child;
    if (plays_here && shown_now->frame_id != frame)
      throw InvalidGoalError(GoalError::kInvalidGoal, "trajectory.header.frame_id: " + quotedText(frame) +
                                                          " is not the frame " + quotedText(shown_now->frame_id) +
                                                          " in which " + quotedText(child) + " moves");
    if (!plays_here && frame != params.frame_id && !tf_._frameExists(frame))
      throw InvalidGoalError(GoalError::kInvalidGoal, "trajectory.header.frame_id: " + quotedText(frame) +
                                                          " is neither ~frame_id " + quotedText(params.frame_id) +
                                                          " nor a frame TF knows");
    if (!plays_here && state_unknown_)
      placeFromMeasurement(frame, child, now, params);
    const GoalStart begin = checkGoalStart(
        trajectory, stamp, now,
        [&](Nanoseconds instant) -> std::optional<PlaybackState> {
          std::optional<PlaybackState> s = playback_.at(instant);
          if (s && s->child_frame_id != child)
            return std::nullopt;
          return s;
        },
        params.start_tolerance_linear, params.start_tolerance_angular);

    std::lock_guard<std::mutex> lock(mutex_);
    const std::string tag = kGoalTagPrefix + std::to_string(next_goal_++);
    if (active_)
    {
      FollowTrajectoryResult replaced;
      replaced.error_string = "replaced by the goal " + handle.getGoalID().id;
      active_->handle.setCanceled(replaced, replaced.error_string);
      active_.reset();
    }
    handle.setAccepted("starts at time_from_start " + formatNumber(begin.time) + " s");
    const double end_time = trajectory.endTime();
    const Pose<double> last = trajectory.stateAt(end_time).pose;
    Motion motion = trajectory.motion(frame, child);
    motion.tag = tag;
    playback_.play(std::move(motion), stamp, nanosecondsOf(ros::Time::now()));
    owns_frame_ = true;
    active_.emplace(
        Active{ handle, tag, frame, stamp, last, GoalSupervisor(tolerances, stamp + toNanoseconds(end_time), last) });
  }
  catch (const InvalidGoalError& e)
  {
    result.error_code = static_cast<int>(e.code());
    result.error_string = boundedMessage(e.what());
    handle.setRejected(result, result.error_string);
  }
  catch (const std::invalid_argument& e)  // the core's other errors (antipodal points, limits): the goal's content
  {
    result.error_code = FollowTrajectoryResult::INVALID_GOAL;
    result.error_string = boundedMessage(e.what());
    handle.setRejected(result, result.error_string);
  }
}

StopLimits stopLimitsOf(const NodeParameters& params)
{
  StopLimits limits;
  limits.max_linear_acceleration = params.max_linear_acceleration;
  limits.max_angular_acceleration = params.max_angular_acceleration;
  limits.max_linear_jerk = params.max_linear_jerk;
  limits.max_angular_jerk = params.max_angular_jerk;
  limits.stop_time = params.stop_time;
  return limits;
}

Nanoseconds stopStart(Nanoseconds now)
{
  return now + toNanoseconds(kStopLead);
}

Pose<double> FollowTrajectoryServer::stopFrame(Nanoseconds now, const NodeParameters& params)
{
  const Nanoseconds rest = playback_.stop(stopStart(now), stopLimitsOf(params));
  const std::optional<PlaybackState> held = playback_.at(rest);
  return held ? held->sample.pose : Pose<double>();
}

void FollowTrajectoryServer::onCancel(GoalHandle handle)
{
  const NodeParameters params = parameters_();
  std::lock_guard<std::mutex> publishing(publish_mutex_);
  std::lock_guard<std::mutex> lock(mutex_);
  if (!active_ || !(active_->handle == handle))
    return;
  FollowTrajectoryResult result;
  result.stopped_at = toMsg(stopFrame(nanosecondsOf(ros::Time::now()), params));
  result.error_string = "cancelled: the frame stops along its path";
  handle.setCanceled(result, result.error_string);
  active_.reset();
}

std::optional<FollowTrajectoryServer::Measurement> FollowTrajectoryServer::measured(const std::string& frame,
                                                                                    const NodeParameters& params) const
{
  if (params.actual_frame.empty())
    return std::nullopt;
  try
  {
    const geometry_msgs::TransformStamped latest = tf_.lookupTransform(frame, params.actual_frame, ros::Time(0));
    return Measurement{ fromMsg(latest.transform), nanosecondsOf(latest.header.stamp) };
  }
  catch (const tf2::TransformException& e)
  {
    ROS_WARN_STREAM_THROTTLE(1.0, "~actual_frame " << params.actual_frame << " in " << frame
                                                   << " is not available: " << e.what());
    return std::nullopt;
  }
}

void FollowTrajectoryServer::feedbackCallback(const ros::TimerEvent& /*event*/)
{
  rememberShownFrame(nanosecondsOf(ros::Time::now()));
  const NodeParameters params = parameters_();
  std::lock_guard<std::mutex> publishing(publish_mutex_);
  std::lock_guard<std::mutex> lock(mutex_);
  if (!active_)
    return;
  const ros::Time now_time = ros::Time::now();
  const Nanoseconds now = nanosecondsOf(now_time);
  const std::optional<PlaybackState> shown = playback_.at(now);
  // Before its start instant the goal is not shown yet (a splice ahead): the setpoint is what plays.
  const TrajectorySample desired = shown ? shown->sample : TrajectorySample();
  const std::optional<Measurement> measurement = measured(active_->frame_id, params);
  const std::optional<Pose<double>> actual =
      measurement ? std::optional<Pose<double>>(measurement->pose) : std::nullopt;
  // The measurement against the setpoint of its own instant (goal_execution.h, measurementInstant).
  Pose<double> reference = desired.pose;
  if (measurement)
    if (const std::optional<PlaybackState> then = playback_.at(measurementInstant(measurement->stamp, now)))
      reference = then->sample.pose;
  const GoalProgress progress = active_->supervisor.update(now, reference, actual);

  FollowTrajectoryFeedback feedback;
  feedback.header.stamp = now_time;
  feedback.header.frame_id = active_->frame_id;
  feedback.time_from_start = secondsBetween(active_->stamp, now);
  toMsg(desired.pose, feedback.desired);
  feedback.desired_velocity = toMsg(desired.velocity);
  toMsg(actual ? *actual : desired.pose, feedback.actual);
  feedback.linear_error = active_->supervisor.error().linear;
  feedback.angular_error = active_->supervisor.error().angular;
  active_->handle.publishFeedback(feedback);

  FollowTrajectoryResult result;
  switch (progress)
  {
    case GoalProgress::kRunning:
      return;
    case GoalProgress::kSucceeded:
      result.error_code = FollowTrajectoryResult::SUCCESSFUL;
      result.stopped_at = toMsg(active_->last);
      active_->handle.setSucceeded(result);
      break;
    case GoalProgress::kPathToleranceViolated:
      result.error_code = FollowTrajectoryResult::PATH_TOLERANCE_VIOLATED;
      result.error_string = active_->supervisor.message();
      result.stopped_at = toMsg(stopFrame(now, params));
      active_->handle.setAborted(result, result.error_string);
      break;
    case GoalProgress::kGoalToleranceViolated:
      result.error_code = FollowTrajectoryResult::GOAL_TOLERANCE_VIOLATED;
      result.error_string = active_->supervisor.message();
      result.stopped_at = toMsg(desired.pose);
      active_->handle.setAborted(result, result.error_string);
      break;
  }
  active_.reset();
}

void FollowTrajectoryServer::commandCallback(const ros::TimerEvent& /*event*/)
{
  const ros::Time now = ros::Time::now();
  const std::optional<PlaybackState> shown = playback_.at(nanosecondsOf(now));
  if (!shown || shown->tag.rfind(kGoalTagPrefix, 0) != 0)
    return;
  geometry_msgs::PoseStamped command;
  command.header.stamp = now;
  command.header.frame_id = shown->frame_id;
  command.pose = toMsg(shown->sample.pose);
  command_pub_.publish(command);
}

}  // namespace se3_interpolation
