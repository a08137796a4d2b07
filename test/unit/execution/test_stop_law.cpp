// The stop law (execution/stop_law.h) through Playback::stop, without ROS: on a straight line at
// constant speed it is the closed-form jerk-limited stop (rest after v/A + A/J); cancelling the
// quintic interpolation of a planner's jerk-limited goal (execution/goal_trajectory.h) anywhere
// along it, the played acceleration and jerk, from the played states and their finite
// differences, stay within the bounds (or within the goal's own peaks where its interpolation
// overshoots them), the acceleration is continuous at the cancel and at rest, and the frame stays
// on the goal's path.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <vector>

#include "se3_interpolation/execution/goal_trajectory.h"
#include "se3_interpolation/execution/playback.h"
#include "se3_interpolation/planner/planner.h"
#include "test_utils.h"

using namespace se3_interpolation;

namespace
{
constexpr Nanoseconds kSecond = 1000000000;
/// The finite differences' step: 0.1 ms.
constexpr Nanoseconds kStep = 100000;

StopLimits limits(double A_lin, double A_ang, double J_lin, double J_ang)
{
  StopLimits l;
  l.max_linear_acceleration = A_lin;
  l.max_angular_acceleration = A_ang;
  l.max_linear_jerk = J_lin;
  l.max_angular_jerk = J_ang;
  return l;
}

/// x(t) = v t along the world x axis, no rotation.
Motion constantSpeedLine(double v, double duration)
{
  Motion m;
  m.state_at = [v](double t) {
    TrajectorySample s;
    s.time = t;
    s.pose.p = Eigen::Vector3d(v * t, 0.0, 0.0);
    s.velocity.linear = Eigen::Vector3d(v, 0.0, 0.0);
    return s;
  };
  m.duration = duration;
  m.frame_id = "map";
  m.child_frame_id = "tool";
  return m;
}

/// The largest played linear and angular accelerations (as shown) and jerks (central differences
/// of the shown accelerations) on [from, to].
struct Peaks
{
  double acceleration[2] = { 0.0, 0.0 };
  double jerk[2] = { 0.0, 0.0 };
};

Peaks playedPeaks(const Playback& p, Nanoseconds from, Nanoseconds to)
{
  const double h = 1e-9 * static_cast<double>(kStep);
  Peaks peaks;
  for (Nanoseconds t = from; t <= to; t += kStep)
  {
    const TrajectorySample before = p.at(t - kStep)->sample, now = p.at(t)->sample, after = p.at(t + kStep)->sample;
    const Eigen::Vector3d a[2] = { now.acceleration.linear, now.acceleration.angular };
    const Eigen::Vector3d j[2] = { (after.acceleration.linear - before.acceleration.linear) / (2 * h),
                                   (after.acceleration.angular - before.acceleration.angular) / (2 * h) };
    for (int c = 0; c < 2; ++c)
    {
      peaks.acceleration[c] = std::max(peaks.acceleration[c], a[c].norm());
      peaks.jerk[c] = std::max(peaks.jerk[c], j[c].norm());
    }
  }
  return peaks;
}

/// A planner's rest-to-rest jerk-limited time_optimal motion on the screw geometry through
/// turning waypoints, sampled every 10 ms as a goal's points (what a client sends as a goal).
GoalTrajectory plannedGoal()
{
  TrajectoryRequest r;
  const auto pose = [](double x, double y, double z, double angle, const Eigen::Vector3d& axis) {
    Pose<double> p;
    p.p = Eigen::Vector3d(x, y, z);
    p.q = Quaternion<double>(Eigen::AngleAxisd(angle, axis.normalized()));
    return p;
  };
  r.waypoints = { pose(0.0, 0.0, 0.0, 0.0, { 0, 0, 1 }), pose(0.6, 0.2, 0.1, 0.8, { 0, 1, 1 }),
                  pose(1.0, 0.8, 0.3, 0.3, { 1, 0, 0 }), pose(0.4, 1.2, 0.0, -0.5, { 1, 1, 0 }) };
  r.geometry = "screw";
  r.timing = "time_optimal";
  r.max_linear_velocity = 0.5;
  r.max_angular_velocity = 1.0;
  r.max_linear_acceleration = 1.0;
  r.max_angular_acceleration = 2.0;
  r.max_linear_jerk = 10.0;
  r.max_angular_jerk = 20.0;
  r.sample_period = 0.01;
  const TrajectoryResult result = generate(r, test::unhurriedLimits());
  std::vector<GoalPoint> points;
  for (const TrajectorySample& s : result.samples)
    points.push_back({ s.time, s.pose, s.velocity, s.acceleration });
  return GoalTrajectory(points, GeometryType::kScrew);
}
}  // namespace

// v/A + A/J: τ̈ ramps to −A/v in A/J s, holds, and ramps back (stop_law.h).
TEST(StopLaw, AConstantSpeedLineStopsAsTheJerkLimitedClosedForm)
{
  const double v = 1.2, A = 2.0, J = 20.0;
  Playback p;
  p.play(constantSpeedLine(v, 100.0), 0, 0);
  const Nanoseconds tc = 3 * kSecond;
  const Nanoseconds rest = p.stop(tc, limits(A, 0.0, J, 0.0));
  EXPECT_NEAR(secondsBetween(tc, rest), v / A + A / J, 2e-9);
  // Distance: half the stop's length at speed v (τ̇ falls symmetrically about its middle).
  EXPECT_NEAR(p.at(rest)->sample.pose.p.x() - 3.0 * v, 0.5 * v * (v / A + A / J), 1e-9);
  EXPECT_FALSE(p.at(rest)->moving);
  const Peaks peaks = playedPeaks(p, tc - kSecond / 100, rest + kSecond / 100);
  EXPECT_LE(peaks.acceleration[0], A * (1 + 1e-9));
  EXPECT_LE(peaks.jerk[0], J * (1 + 1e-6));
  EXPECT_NEAR(p.at(tc + kStep)->sample.acceleration.linear.norm(), J * 1e-4, 1e-9) << "acceleration ramps in at J";
  EXPECT_EQ(peaks.acceleration[1], 0.0);
}

// The case and every other: a goal cancelled anywhere — accelerating, cruising, turning,
// braking at its bound — stops within its bounds, acceleration and jerk included.
TEST(StopLaw, AGoalCancelledAnywhereKeepsItsAccelerationAndJerkBounds)
{
  const GoalTrajectory goal = plannedGoal();
  const StopLimits bounds = limits(1.0, 2.0, 10.0, 20.0);
  // The goal's own peaks: its quintic overshoots its samples' bounds a little (goal_trajectory.h);
  // the stop may reach them, never more.
  const MotionPeaks own = goal.peaks();
  const double allowed_acceleration[2] = { std::max(1.0, own[2].value), std::max(2.0, own[3].value) };
  const double allowed_jerk[2] = { std::max(10.0, own[4].value), std::max(20.0, own[5].value) };
  const Nanoseconds end = toNanoseconds(goal.endTime());
  int stopped_before_the_end = 0;
  double longest = 0.0;  // s of the longest stop computation
  for (Nanoseconds tc = kSecond / 50; tc < end; tc += kSecond / 20 + 7 * kStep)
  {
    SCOPED_TRACE(testing::Message() << "cancelled at " << secondsBetween(0, tc) << " s of " << goal.endTime());
    Playback p;
    p.play(goal.motion("map", "tool"), 0, 0);
    const TrajectorySample before = p.at(tc)->sample;
    const auto computing = std::chrono::steady_clock::now();
    const Nanoseconds rest = p.stop(tc, bounds);
    longest = std::max(longest, std::chrono::duration<double>(std::chrono::steady_clock::now() - computing).count());
    ASSERT_GE(rest, tc);
    EXPECT_LE(rest, end + 1);
    stopped_before_the_end += rest < end;
    // Continuous at the cancel: the goal's state there.
    const TrajectorySample at_cancel = p.at(tc)->sample;
    EXPECT_LT((at_cancel.velocity.linear - before.velocity.linear).norm(), 1e-12);
    EXPECT_LT((at_cancel.acceleration.linear - before.acceleration.linear).norm(), 1e-12);
    EXPECT_LT((at_cancel.acceleration.angular - before.acceleration.angular).norm(), 1e-12);
    const Peaks peaks = playedPeaks(p, tc, rest + kSecond / 100);
    for (int c = 0; c < 2; ++c)
    {
      EXPECT_LE(peaks.acceleration[c], allowed_acceleration[c] * (1 + 1e-6)) << (c ? "angular" : "linear");
      // The central differences straddle the cancel and the law's switches: 1 % for their error.
      EXPECT_LE(peaks.jerk[c], allowed_jerk[c] * 1.01) << (c ? "angular" : "linear");
    }
    // At rest on the goal's path, acceleration 0 from both sides.
    const auto at_rest = p.at(rest);
    EXPECT_FALSE(at_rest->moving);
    const Pose<double> on_path = goal.stateAt(at_rest->sample.time).pose;
    EXPECT_LT((at_rest->sample.pose.p - on_path.p).norm(), 1e-12);
    EXPECT_LT(p.at(rest - kStep)->sample.acceleration.linear.norm(), 10.0 * 2e-4 * 1.01);
  }
  EXPECT_GT(stopped_before_the_end, 5) << "the stops are the law's, not the goal's own end";
  // The node starts a stop 50 ms ahead (kStopLead) to have it in place in time.
  std::cout << "longest stop computation: " << 1e3 * longest << " ms\n";
}

// The time a stop takes is bounded by the motion's own end: a goal braking to rest at its bound
// is never slowed further than its own braking.
TEST(StopLaw, NeverLaterThanTheMotionsOwnEnd)
{
  const GoalTrajectory goal = plannedGoal();
  const Nanoseconds end = toNanoseconds(goal.endTime());
  for (Nanoseconds tc = end - kSecond / 2; tc < end; tc += kSecond / 10)
  {
    Playback p;
    p.play(goal.motion("map", "tool"), 0, 0);
    EXPECT_LE(p.stop(tc, limits(1.0, 2.0, 10.0, 20.0)), end + 1) << tc;
  }
}

// A stop asked for ahead of the present (the node stops from now + 50 ms, the time to compute the
// law): the motion plays on until then, and the stop takes over from its state there.
TEST(StopLaw, AStopFromAnInstantAheadLetsTheMotionPlayUntilThen)
{
  const double v = 0.5;
  Playback p;
  const Motion line = constantSpeedLine(v, 100.0);
  p.play(line, 0, 0);
  const Nanoseconds start = 2 * kSecond + kSecond / 20;
  const Nanoseconds rest = p.stop(start, limits(1.0, 0.0, 10.0, 0.0));
  for (Nanoseconds t = 2 * kSecond; t <= start; t += kStep)
  {
    const auto shown = p.at(t);
    ASSERT_TRUE(shown->moving);
    EXPECT_NEAR(shown->sample.pose.p.x(), v * secondsBetween(0, t), 1e-12) << t;
    EXPECT_NEAR(shown->sample.velocity.linear.x(), v, 1e-12) << t;
  }
  EXPECT_NEAR(secondsBetween(start, rest), v / 1.0 + 1.0 / 10.0, 2e-9);
  const Peaks peaks = playedPeaks(p, 2 * kSecond, rest + kSecond / 100);
  EXPECT_LE(peaks.acceleration[0], 1.0 + 1e-9);
  EXPECT_LE(peaks.jerk[0], 10.0 * (1 + 1e-6));
}
