// The supervision of executed goals without ROS (execution/goal_execution.h): the start rule
// against what a Playback shows (held, moving, nothing), old stamps, the pose error, and the
// supervisor's outcomes for the path and goal tolerances. The references are written here: poses
// placed by hand, errors of known size, instants on both sides of every threshold.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "se3_interpolation/execution/goal_execution.h"

namespace se3_interpolation
{
namespace
{
constexpr Nanoseconds kSecond = 1000000000;

Pose<double> poseAt(double x, double y, double z, double yaw = 0.0)
{
  return Pose<double>(Quaternion<double>(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())), Eigen::Vector3d(x, y, z));
}

GoalPoint restPoint(double t, const Pose<double>& pose)
{
  GoalPoint p;
  p.time_from_start = t;
  p.pose = pose;
  p.velocity = Twist();
  p.acceleration = Twist();
  return p;
}

GoalPoint pointOf(double t, const TrajectorySample& s)
{
  GoalPoint p;
  p.time_from_start = t;
  p.pose = s.pose;
  p.velocity = s.velocity;
  p.acceleration = s.acceleration;
  return p;
}

/// A rest-to-rest move from (0,0,0) to (1,0,0) turning 1 rad, on [0, 2] s: what a Playback shows.
GoalTrajectory played()
{
  return GoalTrajectory({ restPoint(0.0, poseAt(0, 0, 0)), restPoint(2.0, poseAt(1, 0, 0, 1.0)) },
                        GeometryType::kDoubleGeodesic);
}

std::function<std::optional<PlaybackState>(Nanoseconds)> shownBy(const Playback& playback)
{
  return [&playback](Nanoseconds t) { return playback.at(t); };
}

/// The error code of what `f` throws (fails the test when it throws nothing).
template <class F>
GoalError codeOf(F&& f, std::string* message = nullptr)
{
  try
  {
    f();
  }
  catch (const InvalidGoalError& e)
  {
    if (message)
      *message = e.what();
    return e.code();
  }
  ADD_FAILURE() << "no InvalidGoalError";
  return GoalError::kInvalidGoal;
}

TEST(PoseError, DistanceAndAngleOfKnownOffsets)
{
  const Pose<double> a = poseAt(1, 2, 3, 0.3);
  Pose<double> b = poseAt(1, 2 + 0.25, 3, 0.3 + 0.7);
  PoseError e = poseError(a, b);
  EXPECT_NEAR(e.linear, 0.25, 1e-15);
  EXPECT_NEAR(e.angular, 0.7, 1e-14);
  b.q.coeffs() = -b.q.coeffs();  // the same rotation
  e = poseError(a, b);
  EXPECT_NEAR(e.angular, 0.7, 1e-14);
  EXPECT_NEAR(poseError(a, poseAt(1, 2, 3, 0.3 + M_PI - 1e-9)).angular, M_PI - 1e-9, 1e-9);
  EXPECT_EQ(poseError(a, a).angular, 0.0);
}

TEST(GoalStart, NothingPlayedTakesAnyStart)
{
  Playback playback;
  const GoalTrajectory goal({ restPoint(0.5, poseAt(3, 3, 3)), restPoint(1.5, poseAt(4, 3, 3)) },
                            GeometryType::kDoubleGeodesic);
  const GoalStart s = checkGoalStart(goal, 10 * kSecond, 9 * kSecond, shownBy(playback), 0.0, 0.0);
  EXPECT_EQ(s.instant, 10 * kSecond + kSecond / 2);
  EXPECT_EQ(s.time, 0.5);
}

TEST(GoalStart, AtRestTheGoalStartsAtTheHeldPoseWithinTheTolerance)
{
  Playback playback;
  playback.play(played().motion("map", "tool"), 0, 0);
  const Nanoseconds now = 5 * kSecond;  // the move ended at 2 s: held at (1, 0, 0), yaw 1
  auto goalFrom = [](const Pose<double>& start) {
    return GoalTrajectory({ restPoint(0.0, start), restPoint(1.0, poseAt(2, 0, 0)) }, GeometryType::kDoubleGeodesic);
  };
  EXPECT_NO_THROW(checkGoalStart(goalFrom(poseAt(1 + 5e-7, 0, 0, 1.0)), now, now, shownBy(playback), 0.0, 0.0));
  std::string message;
  EXPECT_EQ(codeOf([&] { checkGoalStart(goalFrom(poseAt(1.001, 0, 0, 1.0)), now, now, shownBy(playback), 0.0, 0.0); },
                   &message),
            GoalError::kInvalidGoal);
  EXPECT_NE(message.find("trajectory.points[0]"), std::string::npos) << message;
  EXPECT_NE(message.find("held pose"), std::string::npos) << message;
  EXPECT_NE(message.find("position"), std::string::npos) << message;
  // The path tolerance widens the rest rule (a measured arm is never exactly where it was held).
  EXPECT_NO_THROW(checkGoalStart(goalFrom(poseAt(1.001, 0, 0, 1.0)), now, now, shownBy(playback), 0.002, 0.0));
  EXPECT_EQ(codeOf([&] { checkGoalStart(goalFrom(poseAt(1, 0, 0, 1.01)), now, now, shownBy(playback), 0.002, 0.0); },
                   &message),
            GoalError::kInvalidGoal);
  EXPECT_NE(message.find("orientation"), std::string::npos) << message;
  // At the held pose but moving off: refused, the frame is at rest.
  GoalPoint moving = restPoint(0.0, poseAt(1, 0, 0, 1.0));
  moving.velocity->linear.x() = 1e-3;
  const GoalTrajectory launched({ moving, restPoint(1.0, poseAt(2, 0, 0)) }, GeometryType::kDoubleGeodesic);
  EXPECT_EQ(codeOf([&] { checkGoalStart(launched, now, now, shownBy(playback), 0.0, 0.0); }, &message),
            GoalError::kInvalidGoal);
  EXPECT_NE(message.find("velocity"), std::string::npos) << message;
}

TEST(GoalStart, WhileMovingTheGoalMustStartAtTheFramesStateC2)
{
  Playback playback;
  playback.play(played().motion("map", "tool"), 0, 0);
  const Nanoseconds switch_at = kSecond;  // mid-way: moving
  const std::optional<PlaybackState> shown = playback.at(switch_at);
  ASSERT_TRUE(shown && shown->moving);
  ASSERT_GT(shown->sample.velocity.linear.norm(), 0.1);
  auto spliced = [&](const TrajectorySample& start) {
    return GoalTrajectory({ pointOf(0.0, start), restPoint(2.0, poseAt(0.5, 1.0, 0.0)) }, GeometryType::kDoubleGeodesic);
  };
  const GoalStart s = checkGoalStart(spliced(shown->sample), switch_at, 0, shownBy(playback), 0.0, 0.0);
  EXPECT_EQ(s.instant, switch_at);
  // Each part of the state differs by 1e-5 > kSpliceTolerance in turn: refused, naming it.
  const std::vector<std::pair<std::string, std::function<void(TrajectorySample&)>>> perturbations = {
    { "position", [](TrajectorySample& x) { x.pose.p.y() += 1e-5; } },
    { "orientation", [](TrajectorySample& x) { x.pose.q = x.pose.q * Quaternion<double>(Eigen::AngleAxisd(1e-5, Eigen::Vector3d::UnitX())); } },
    { "velocity", [](TrajectorySample& x) { x.velocity.angular.z() += 1e-5; } },
    { "acceleration", [](TrajectorySample& x) { x.acceleration.linear.x() += 1e-5; } },
  };
  for (const auto& [what, change] : perturbations)
  {
    TrajectorySample start = shown->sample;
    change(start);
    std::string message;
    EXPECT_EQ(codeOf([&] { checkGoalStart(spliced(start), switch_at, 0, shownBy(playback), 0.0, 0.0); }, &message),
              GoalError::kInvalidGoal)
        << what;
    EXPECT_NE(message.find(what), std::string::npos) << message;
    EXPECT_NE(message.find("from_current"), std::string::npos) << message;
  }
  // The path tolerance does not widen the rule while moving: a splice must be exact.
  TrajectorySample off = shown->sample;
  off.pose.p.y() += 1e-5;
  EXPECT_EQ(codeOf([&] { checkGoalStart(spliced(off), switch_at, 0, shownBy(playback), 0.1, 0.1); }),
            GoalError::kInvalidGoal);
}

TEST(GoalStart, OldStamps)
{
  Playback playback;
  playback.play(played().motion("map", "tool"), 0, 0);
  const Nanoseconds now = 100 * kSecond;
  // Wholly past: ended 10 s before now.
  const GoalTrajectory dwell({ restPoint(0.0, poseAt(1, 0, 0, 1.0)), restPoint(20.0, poseAt(1, 0, 0, 1.0)),
                               restPoint(21.0, poseAt(2, 0, 0, 1.0)) },
                             GeometryType::kDoubleGeodesic);
  std::string message;
  EXPECT_EQ(codeOf([&] { checkGoalStart(dwell, now - 31 * kSecond, now, shownBy(playback), 0.0, 0.0); }, &message),
            GoalError::kOldHeaderTimestamp);
  EXPECT_NE(message.find("trajectory.header.stamp"), std::string::npos) << message;
  EXPECT_NE(message.find("ended"), std::string::npos) << message;
  // Started 5 s ago, still dwelling at the held pose: it starts at its point of now.
  const GoalStart s = checkGoalStart(dwell, now - 5 * kSecond, now, shownBy(playback), 0.0, 0.0);
  EXPECT_EQ(s.instant, now);
  EXPECT_DOUBLE_EQ(s.time, 5.0);
  // Started 20.5 s ago: its point of now moves (between 20 and 21 s): not the held state.
  EXPECT_EQ(codeOf([&] { checkGoalStart(dwell, now - 20500000000, now, shownBy(playback), 0.0, 0.0); }, &message),
            GoalError::kOldHeaderTimestamp);
  EXPECT_NE(message.find("started"), std::string::npos) << message;
}

TEST(GoalSupervisor, PathToleranceWhileMoving)
{
  GoalTolerances t;
  t.path_linear = 0.01;
  t.path_angular = 0.1;
  const Pose<double> last = poseAt(1, 0, 0);
  GoalSupervisor s(t, 10 * kSecond, last);
  EXPECT_EQ(s.update(kSecond, poseAt(0, 0, 0), poseAt(0.0099, 0, 0)), GoalProgress::kRunning);
  EXPECT_NEAR(s.error().linear, 0.0099, 1e-15);
  EXPECT_EQ(s.update(kSecond, poseAt(0, 0, 0), std::nullopt), GoalProgress::kRunning) << "nothing measured";
  EXPECT_EQ(s.update(2 * kSecond, poseAt(0, 0, 0), poseAt(0, 0, 0, 0.11)), GoalProgress::kPathToleranceViolated);
  EXPECT_NE(s.message().find("path_tolerance_angular"), std::string::npos) << s.message();
  GoalSupervisor linear(t, 10 * kSecond, last);
  EXPECT_EQ(linear.update(2 * kSecond, poseAt(0, 0, 0), poseAt(0, 0.0101, 0)), GoalProgress::kPathToleranceViolated);
  EXPECT_NE(linear.message().find("path_tolerance_linear"), std::string::npos) << linear.message();
}

TEST(GoalSupervisor, MeasurementInstant)
{
  const Nanoseconds now = 100 * kSecond;
  const Nanoseconds oldest = now - 200000000;  // kMaxMeasurementAge = 0.2 s before now
  EXPECT_EQ(measurementInstant(now - 80000000, now), now - 80000000) << "a fresh measurement: its stamp";
  EXPECT_EQ(measurementInstant(oldest, now), oldest);
  EXPECT_EQ(measurementInstant(oldest - 1, now), oldest) << "older: as if 0.2 s old";
  EXPECT_EQ(measurementInstant(0, now), oldest) << "a stamp of a driver that stopped long ago";
  EXPECT_EQ(measurementInstant(now + kSecond, now), now) << "ahead of now (clock skew): now";
}

/// A measurement that arrives late (stamped 80 ms before the check) of an arm that is exactly on
/// the path: compared with the setpoint of its stamp it is on the path; compared with the setpoint
/// of the check's instant it would be several centimetres off, the failure the rule removes. A
/// stalled arm (measured at the start, stamped now) is still seen off the path.
TEST(GoalSupervisor, AMeasurementIsComparedAtItsOwnInstant)
{
  Playback playback;
  playback.play(played().motion("map", "tool"), 0, 0);
  GoalTolerances t;
  t.path_linear = 0.01;
  const Nanoseconds now = kSecond;  // mid-way, at the peak speed (15/16 m/s: a quintic from rest to rest)
  const Nanoseconds stamp = now - 80000000;
  const Pose<double> measured = playback.at(stamp)->sample.pose;
  const Pose<double> setpoint_now = playback.at(now)->sample.pose;
  ASSERT_GT(poseError(setpoint_now, measured).linear, 0.03) << "the reference moves between the two instants";
  GoalSupervisor s(t, 2 * kSecond, poseAt(1, 0, 0, 1.0));
  EXPECT_EQ(s.update(now, playback.at(measurementInstant(stamp, now))->sample.pose, measured), GoalProgress::kRunning);
  EXPECT_LT(s.error().linear, 1e-12);
  GoalSupervisor stalled(t, 2 * kSecond, poseAt(1, 0, 0, 1.0));
  EXPECT_EQ(stalled.update(now, playback.at(measurementInstant(now, now))->sample.pose, poseAt(0, 0, 0)),
            GoalProgress::kPathToleranceViolated);
}

TEST(GoalSupervisor, GoalToleranceAfterTheEnd)
{
  GoalTolerances t;
  t.goal_linear = 0.001;
  t.goal_time = 0.5;
  const Pose<double> last = poseAt(1, 0, 0);
  const Nanoseconds end = 10 * kSecond;
  {
    GoalSupervisor s(t, end, last);
    EXPECT_EQ(s.update(end - 1, last, poseAt(0.5, 0, 0)), GoalProgress::kRunning) << "no path tolerance";
    EXPECT_EQ(s.update(end, last, poseAt(1.0005, 0, 0)), GoalProgress::kSucceeded);
  }
  {
    GoalSupervisor s(t, end, last);
    EXPECT_EQ(s.update(end + kSecond / 4, last, poseAt(1.002, 0, 0)), GoalProgress::kRunning) << "still arriving";
    EXPECT_EQ(s.update(end + kSecond / 2 + 1, last, poseAt(1.002, 0, 0)), GoalProgress::kGoalToleranceViolated);
    EXPECT_NE(s.message().find("goal_tolerance_linear"), std::string::npos) << s.message();
  }
  {
    GoalSupervisor s(t, end, last);
    EXPECT_EQ(s.update(end + kSecond, last, std::nullopt), GoalProgress::kGoalToleranceViolated);
    EXPECT_NE(s.message().find("not been seen"), std::string::npos) << s.message();
  }
  {
    GoalSupervisor unchecked(GoalTolerances(), end, last);
    EXPECT_EQ(unchecked.update(end - 1, last, std::nullopt), GoalProgress::kRunning);
    EXPECT_EQ(unchecked.update(end, last, std::nullopt), GoalProgress::kSucceeded);
  }
}

}  // namespace
}  // namespace se3_interpolation
