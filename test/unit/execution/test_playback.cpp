// Playback (execution/playback.h), without ROS: the clock in integer nanoseconds, holding before
// and after a motion, looping, splicing a replan at its start, hold, the stop ramp, the bounded
// stop and the motions' tags, each against motions written here in closed form (a line at
// constant acceleration, a circle, a rotation).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <thread>

#include "se3_interpolation/execution/playback.h"

using namespace se3_interpolation;

namespace
{
constexpr Nanoseconds kSecond = 1000000000;

/// x(t) = x0 + v t + a t²/2 along the world x axis, no rotation, on [start, start + duration].
Motion line(double x0, double v, double a, double start, double duration, const std::string& child = "tool")
{
  Motion m;
  m.state_at = [x0, v, a](double t) {
    TrajectorySample s;
    s.time = t;
    s.pose.p = Eigen::Vector3d(x0 + v * t + 0.5 * a * t * t, 0.0, 0.0);
    s.velocity.linear = Eigen::Vector3d(v + a * t, 0.0, 0.0);
    s.acceleration.linear = Eigen::Vector3d(a, 0.0, 0.0);
    return s;
  };
  m.start_time = start;
  m.duration = duration;
  m.frame_id = "map";
  m.child_frame_id = child;
  return m;
}

/// A unit circle in the xy plane at angular rate w, the body turning with it (yaw = w t).
Motion circle(double w, double duration)
{
  Motion m;
  m.state_at = [w](double t) {
    TrajectorySample s;
    s.time = t;
    const double c = std::cos(w * t), sn = std::sin(w * t);
    s.pose.p = Eigen::Vector3d(c, sn, 0.0);
    s.pose.q = Eigen::Quaterniond(Eigen::AngleAxisd(w * t, Eigen::Vector3d::UnitZ()));
    s.velocity.linear = Eigen::Vector3d(-w * sn, w * c, 0.0);
    s.velocity.angular = Eigen::Vector3d(0.0, 0.0, w);
    s.acceleration.linear = Eigen::Vector3d(-w * w * c, -w * w * sn, 0.0);
    return s;
  };
  m.duration = duration;
  m.frame_id = "map";
  m.child_frame_id = "tool";
  return m;
}

double xAt(const Playback& p, Nanoseconds t)
{
  return p.at(t)->sample.pose.p.x();
}
}  // namespace

TEST(Playback, NothingIsShownBeforeTheFirstMotion)
{
  Playback p;
  EXPECT_FALSE(p.at(0).has_value());
  p.hold(0);
  EXPECT_EQ(p.stop(5, 1.0), 5);
  EXPECT_FALSE(p.at(10).has_value());
  EXPECT_THROW(p.play(Motion(), 0, 0), std::invalid_argument);
}

TEST(Playback, ShowsTheMotionOnItsSpanAndHoldsItsEndsAtRest)
{
  Playback p;
  const Nanoseconds stamp = 1700000000 * kSecond;  // 2023: a double of seconds has 0.2 us here
  p.play(line(1.0, 2.0, 0.0, 0.5, 2.0), stamp, stamp);
  // Before the start: the start pose, at rest.
  auto before = p.at(stamp + kSecond / 4);
  ASSERT_TRUE(before);
  EXPECT_FALSE(before->moving);
  EXPECT_DOUBLE_EQ(before->sample.pose.p.x(), 2.0);
  EXPECT_EQ(before->sample.velocity.linear.norm(), 0.0);
  // On the span: the motion at its own time, to the nanosecond.
  for (Nanoseconds dt : { kSecond / 2, kSecond / 2 + 1, kSecond, 2 * kSecond + kSecond / 2 - 1 })
  {
    auto s = p.at(stamp + dt);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->moving);
    EXPECT_NEAR(s->sample.time, static_cast<double>(dt) * 1e-9, 1e-15);
    EXPECT_NEAR(s->sample.pose.p.x(), 1.0 + 2.0 * static_cast<double>(dt) * 1e-9, 1e-12);
    EXPECT_EQ(s->sample.velocity.linear.x(), 2.0);
    EXPECT_EQ(s->frame_id, "map");
    EXPECT_EQ(s->child_frame_id, "tool");
  }
  // From the end on: the last pose, at rest.
  auto after = p.at(stamp + 100 * kSecond);
  EXPECT_FALSE(after->moving);
  EXPECT_DOUBLE_EQ(after->sample.pose.p.x(), 6.0);
  EXPECT_EQ(after->sample.velocity.linear.norm(), 0.0);
  EXPECT_EQ(after->sample.acceleration.linear.norm(), 0.0);
}

TEST(Playback, AStampFarAheadOrBehindNeitherThrowsNorOverflows)
{
  Playback p;
  const Nanoseconds far = (Nanoseconds(1) << 33) * kSecond;  // 2^33 s: beyond ros::Duration's 2^31 s
  p.play(line(0.0, 1.0, 0.0, 0.0, 1.0), far, 0);
  EXPECT_FALSE(p.at(0)->moving);
  EXPECT_DOUBLE_EQ(xAt(p, 0), 0.0);
  EXPECT_DOUBLE_EQ(xAt(p, far + kSecond / 2), 0.5);
  EXPECT_EQ(toNanoseconds(1e30), toNanoseconds(1e31));  // saturated
  EXPECT_EQ(toNanoseconds(-1e30), -toNanoseconds(1e30));
  EXPECT_EQ(toNanoseconds(std::nan("")), 0);
  EXPECT_EQ(toNanoseconds(1.5e-9), 2);
}

TEST(Playback, LoopRepeatsTheSpanForever)
{
  Playback p;
  p.setLoop(true);
  EXPECT_TRUE(p.loop());
  p.play(line(0.0, 1.0, 0.0, 1.0, 2.0), 0, 0);
  // The span [1, 3] s repeats: t = 3.5 s shows 1.5 s, t = 0.5 s shows 2.5 s, t = 1e6 + 0.25 s
  // shows 2.25 s.
  EXPECT_NEAR(xAt(p, 3 * kSecond + kSecond / 2), 1.5, 1e-12);
  EXPECT_NEAR(xAt(p, kSecond / 2), 2.5, 1e-12);
  EXPECT_NEAR(xAt(p, 1000000 * kSecond + kSecond / 4), 2.25, 1e-6);
  EXPECT_TRUE(p.at(1000000 * kSecond)->moving);
  p.setLoop(false);
  EXPECT_NEAR(xAt(p, 3 * kSecond + kSecond / 2), 3.0, 1e-12);
}

TEST(Playback, AReplanIsSplicedAtItsStart)
{
  Playback p;
  p.play(line(0.0, 1.0, 0.0, 0.0, 10.0, "tool"), 0, 0);
  // At t = 1 s a replan starting at t = 2 s (stamp 1.5 s, start_time 0.5 s) is played.
  p.play(line(100.0, -1.0, 0.0, 0.5, 5.0, "tool"), 3 * kSecond / 2, kSecond);
  EXPECT_NEAR(xAt(p, kSecond + kSecond / 2), 1.5, 1e-12);      // still the first
  EXPECT_NEAR(xAt(p, 2 * kSecond - 1), 2.0, 1e-8);              // the first, up to the switch
  EXPECT_NEAR(xAt(p, 2 * kSecond), 100.0 - 0.5, 1e-12);        // the replan from its start
  // A second replan, played at 1.2 s and starting at 1.8 s: the pending one is never shown.
  p.play(line(50.0, 0.0, 0.0, 0.0, 5.0, "tool"), 18 * kSecond / 10, 12 * kSecond / 10);
  EXPECT_NEAR(xAt(p, 17 * kSecond / 10), 1.7, 1e-12);
  EXPECT_NEAR(xAt(p, 19 * kSecond / 10), 50.0, 1e-12);
  EXPECT_NEAR(xAt(p, 3 * kSecond), 50.0, 1e-12);
}

TEST(Playback, AReplanStartingAfterAPendingOneKeepsBoth)
{
  Playback p;
  p.play(line(0.0, 1.0, 0.0, 0.0, 10.0), 0, 0);
  p.play(line(10.0, 0.0, 0.0, 0.0, 10.0), kSecond, 0);          // pending from 1 s
  p.play(line(20.0, 0.0, 0.0, 0.0, 10.0), 2 * kSecond, kSecond / 2);  // from 2 s, played at 0.5 s
  EXPECT_NEAR(xAt(p, kSecond / 2), 0.5, 1e-12);  // the first
  EXPECT_NEAR(xAt(p, 3 * kSecond / 2), 10.0, 1e-12);  // the pending one
  EXPECT_NEAR(xAt(p, 5 * kSecond / 2), 20.0, 1e-12);  // the newest
}

TEST(Playback, AMotionOfAnotherFrameReplacesEverythingAtOnce)
{
  Playback p;
  p.play(line(0.0, 1.0, 0.0, 0.0, 10.0, "tool"), 0, 0);
  p.play(line(5.0, 0.0, 0.0, 1.0, 1.0, "other"), kSecond, kSecond / 2);
  auto s = p.at(kSecond);
  EXPECT_EQ(s->child_frame_id, "other");
  EXPECT_FALSE(s->moving);
  EXPECT_DOUBLE_EQ(s->sample.pose.p.x(), 5.0);
}

TEST(Playback, HoldKeepsThePoseShownThenAtRest)
{
  Playback p;
  p.setLoop(true);
  p.play(line(0.0, 1.0, 0.5, 0.0, 4.0), 0, 0);
  p.hold(5 * kSecond);  // looped: 1 s into the span, x = 1.25
  for (Nanoseconds t : { 5 * kSecond, 6 * kSecond, 1000 * kSecond })
  {
    auto s = p.at(t);
    EXPECT_FALSE(s->moving);
    EXPECT_NEAR(s->sample.pose.p.x(), 1.25, 1e-12);
    EXPECT_EQ(s->sample.velocity.linear.norm(), 0.0);
    EXPECT_EQ(s->sample.acceleration.linear.norm(), 0.0);
  }
}

// The stop ramp against the closed form for a motion at constant velocity v: the speed is
// v (1 − 3σ² + 2σ³), the distance v T/2, and the acceleration 6 v (σ² − σ)/T; velocity and
// acceleration are continuous at the stop's start and zero at its end.
TEST(Playback, StopRampComesToRestAlongThePathWithContinuousAcceleration)
{
  Playback p;
  const double v = 0.8, T = 0.5;
  p.play(line(0.0, v, 0.0, 0.0, 100.0), 0, 0);
  const Nanoseconds tc = 2 * kSecond;
  const auto before = p.at(tc);
  EXPECT_EQ(p.stop(tc, T), tc + kSecond / 2);
  for (int k = 0; k <= 100; ++k)
  {
    const double sigma = k / 100.0;
    const auto s = p.at(tc + toNanoseconds(sigma * T));
    const double x = 2.0 * v + v * T * (sigma - std::pow(sigma, 3) + 0.5 * std::pow(sigma, 4));
    EXPECT_NEAR(s->sample.pose.p.x(), x, 1e-9) << sigma;
    EXPECT_NEAR(s->sample.velocity.linear.x(), v * (1 - 3 * sigma * sigma + 2 * std::pow(sigma, 3)), 1e-9) << sigma;
    EXPECT_NEAR(s->sample.acceleration.linear.x(), sigma < 1.0 ? 6.0 * v * (sigma * sigma - sigma) / T : 0.0, 1e-9)
        << sigma;
    EXPECT_EQ(s->sample.pose.p.y(), 0.0);
  }
  const auto start = p.at(tc);
  EXPECT_NEAR(start->sample.velocity.linear.x(), before->sample.velocity.linear.x(), 1e-12);
  EXPECT_NEAR(start->sample.acceleration.linear.x(), before->sample.acceleration.linear.x(), 1e-12);
  const auto rest = p.at(tc + 10 * kSecond);
  EXPECT_FALSE(rest->moving);
  EXPECT_NEAR(rest->sample.pose.p.x(), 2.0 * v + v * T / 2, 1e-9);
  EXPECT_EQ(rest->sample.velocity.linear.norm(), 0.0);
}

// On a curved, turning motion: the ramp's reported velocity and acceleration are the finite
// differences of its poses and velocities, and the path stays on the circle.
TEST(Playback, StopRampOfACurvedMotionIsConsistentAndStaysOnThePath)
{
  Playback p;
  p.setLoop(true);
  const double w = 2.0, T = 0.7;
  p.play(circle(w, 3.0), 0, 0);
  const Nanoseconds tc = 7 * kSecond;  // looped
  p.stop(tc, T);
  const Nanoseconds hn = 10000;  // 10 us: central differences on the nanosecond clock
  const double h = static_cast<double>(hn) * 1e-9;
  for (int k = 0; k < 50; ++k)
  {
    const Nanoseconds t = toNanoseconds((k + 0.5) / 50.0 * T);
    const auto s = p.at(tc + t);
    const auto a = p.at(tc + t - hn);
    const auto b = p.at(tc + t + hn);
    EXPECT_NEAR(s->sample.pose.p.norm(), 1.0, 1e-12);
    const Eigen::Vector3d v_fd = (b->sample.pose.p - a->sample.pose.p) / (2 * h);
    const Eigen::Vector3d a_fd = (b->sample.velocity.linear - a->sample.velocity.linear) / (2 * h);
    EXPECT_LT((v_fd - s->sample.velocity.linear).norm(), 1e-5) << t;
    EXPECT_LT((a_fd - s->sample.acceleration.linear).norm(), 1e-4) << t;
    const Eigen::AngleAxisd turn(b->sample.pose.q * a->sample.pose.q.inverse());
    EXPECT_NEAR(turn.angle() / (2 * h), s->sample.velocity.angular.z(), 1e-5) << t;
  }
}

TEST(Playback, StoppingWhatIsAtRestHoldsIt)
{
  Playback p;
  p.play(line(0.0, 1.0, 0.0, 0.0, 1.0), 0, 0);
  EXPECT_EQ(p.stop(5 * kSecond, 1.0), 5 * kSecond);
  EXPECT_NEAR(xAt(p, 6 * kSecond), 1.0, 1e-12);
  for (double bad : { 0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity() })
    EXPECT_THROW(p.stop(0, bad), std::invalid_argument) << bad;
}

// The bounded stop (StopLimits with acceleration bounds), against closed forms written here: a
// line at constant speed v stopped at deceleration A needs v/A s and v²/(2A) m; the played
// acceleration, from finite differences of the played velocities, stays within the bounds.
namespace
{
constexpr Nanoseconds kFiniteDifferenceStep = 100000;  // 0.1 ms
/// A played acceleration may exceed its bound by rounding only.
constexpr double kBoundSlack = 1.0 + 1e-6;
/// Without a jerk bound the stop's acceleration ramps in and out over a tenth of v/A each
/// (stop_law.h): its distance and time stay within 1/0.9 of the closed form at the bound.
constexpr double kMarginFactor = 1.0 / 0.9;

/// A pure rotation about z at rate w (yaw = w t), the origin fixed.
Motion yawing(double w, double duration)
{
  Motion m;
  m.state_at = [w](double t) {
    TrajectorySample s;
    s.time = t;
    s.pose.q = Eigen::Quaterniond(Eigen::AngleAxisd(w * t, Eigen::Vector3d::UnitZ()));
    s.velocity.angular = Eigen::Vector3d(0.0, 0.0, w);
    return s;
  };
  m.duration = duration;
  m.frame_id = "map";
  m.child_frame_id = "tool";
  return m;
}

StopLimits bounds(double linear, double angular)
{
  StopLimits limits;
  limits.max_linear_acceleration = linear;
  limits.max_angular_acceleration = angular;
  return limits;
}

/// The largest linear and angular accelerations played on (from, to), from central differences
/// of the played velocities every 0.1 ms.
std::pair<double, double> peakAccelerations(const Playback& p, Nanoseconds from, Nanoseconds to)
{
  const double h = static_cast<double>(kFiniteDifferenceStep) * 1e-9;
  double linear = 0.0, angular = 0.0;
  for (Nanoseconds t = from + kFiniteDifferenceStep; t + kFiniteDifferenceStep < to; t += kFiniteDifferenceStep)
  {
    const auto a = p.at(t - kFiniteDifferenceStep);
    const auto b = p.at(t + kFiniteDifferenceStep);
    linear = std::max(linear, (b->sample.velocity.linear - a->sample.velocity.linear).norm() / (2 * h));
    angular = std::max(angular, (b->sample.velocity.angular - a->sample.velocity.angular).norm() / (2 * h));
  }
  return { linear, angular };
}
}  // namespace

TEST(Playback, BoundedStopOfAConstantSpeedLineTakesVOverAAndVSquaredOverTwoA)
{
  Playback p;
  const double v = 1.2, A = 2.0;
  p.play(line(0.0, v, 0.0, 0.0, 100.0), 0, 0);
  const Nanoseconds tc = 3 * kSecond;
  const auto before = p.at(tc);
  const Nanoseconds rest = p.stop(tc, bounds(A, 1.0));
  const double time = secondsBetween(tc, rest);
  EXPECT_GE(time, v / A - 1e-9);
  EXPECT_LE(time, kMarginFactor * v / A);
  const auto end = p.at(rest);
  EXPECT_FALSE(end->moving);
  EXPECT_EQ(end->sample.velocity.linear.norm(), 0.0);
  const double distance = end->sample.pose.p.x() - 3.0 * v;
  EXPECT_GE(distance, v * v / (2 * A) - 1e-9);
  EXPECT_LE(distance, kMarginFactor * v * v / (2 * A));
  EXPECT_NEAR(p.at(rest + 10 * kSecond)->sample.pose.p.x(), end->sample.pose.p.x(), 1e-15);
  // The velocity is continuous at the cancel instant: equal there, within A δ just after.
  EXPECT_NEAR((p.at(tc)->sample.velocity.linear - before->sample.velocity.linear).norm(), 0.0, 1e-12);
  const Nanoseconds delta = 1000;
  EXPECT_LE((p.at(tc + delta)->sample.velocity.linear - before->sample.velocity.linear).norm(),
            A * kBoundSlack * static_cast<double>(delta) * 1e-9);
  EXPECT_LE(peakAccelerations(p, tc, rest + kSecond).first, A * kBoundSlack);
  // Braking hard: past the middle of the stop the speed has fallen by at least half A t.
  const Nanoseconds middle = tc + (rest - tc) / 2;
  EXPECT_LE(p.at(middle)->sample.velocity.linear.x(), v - 0.5 * A * secondsBetween(tc, middle));
  for (Nanoseconds t = tc; t <= rest; t += kSecond / 100)
    EXPECT_EQ(p.at(t)->sample.pose.p.y(), 0.0);
}

TEST(Playback, BoundedStopOfACurvedMotionStaysOnThePathWithinBothBounds)
{
  Playback p;
  p.setLoop(true);
  const double w = 1.5;  // centripetal w² = 2.25 m/s² on the unit circle, angular rate w
  const Motion original = circle(w, 3.0);
  p.play(original, 0, 0);
  const Nanoseconds tc = 7 * kSecond + kSecond / 3;  // looped: 1.333 s into the span
  const auto before = p.at(tc);
  const double A_lin = 4.0, A_ang = 3.0;
  const Nanoseconds rest = p.stop(tc, bounds(A_lin, A_ang));
  EXPECT_GT(rest, tc);
  EXPECT_NEAR((p.at(tc)->sample.velocity.linear - before->sample.velocity.linear).norm(), 0.0, 1e-12);
  EXPECT_NEAR((p.at(tc)->sample.velocity.angular - before->sample.velocity.angular).norm(), 0.0, 1e-12);
  // On the path: the pose shown is the original motion's at the reported time τ.
  for (Nanoseconds t = tc; t <= rest + kSecond; t += kSecond / 200)
  {
    const auto s = p.at(t);
    const TrajectorySample on_path = original.state_at(s->sample.time);
    EXPECT_LT((s->sample.pose.p - on_path.pose.p).norm(), 1e-12) << t;
    EXPECT_LT(s->sample.pose.q.angularDistance(on_path.pose.q), 1e-9) << t;
    EXPECT_GE(s->sample.time, 0.0);
    EXPECT_LE(s->sample.time, 3.0);
  }
  const auto peaks = peakAccelerations(p, tc, rest + kSecond);
  EXPECT_LE(peaks.first, A_lin * kBoundSlack);
  EXPECT_LE(peaks.second, A_ang * kBoundSlack);
  EXPECT_FALSE(p.at(rest)->moving);
}

// x(t) = v0 t − A t²/2 ends at rest at v0/A, braking at exactly the bound A all along: no
// braking can be added, and the stop must not take longer than the motion itself.
TEST(Playback, AMotionBrakingAtTheBoundStopsNoLaterThanItWould)
{
  Playback p;
  const double v0 = 2.0, A = 1.0;
  p.play(line(0.0, v0, -A, 0.0, v0 / A), 0, 0);
  const Nanoseconds tc = kSecond / 2;
  const Nanoseconds rest = p.stop(tc, bounds(A, 0.0));
  const Nanoseconds own_end = toNanoseconds(v0 / A);
  EXPECT_LE(rest, own_end + 1000);  // within 1 µs of rounding
  EXPECT_LE(peakAccelerations(p, tc, rest + kSecond).first, A * kBoundSlack);
  const auto end = p.at(rest);
  EXPECT_FALSE(end->moving);
  EXPECT_LE(end->sample.pose.p.x(), v0 * v0 / (2 * A) + 1e-9);
}

TEST(Playback, BoundedStopOfARotationUsesTheAngularBound)
{
  Playback p;
  const double w = 1.5, B = 3.0;
  p.play(yawing(w, 100.0), 0, 0);
  const Nanoseconds tc = kSecond;
  const Nanoseconds rest = p.stop(tc, bounds(0.5, B));
  const double time = secondsBetween(tc, rest);
  EXPECT_GE(time, w / B - 1e-9);
  EXPECT_LE(time, kMarginFactor * w / B);
  const auto end = p.at(rest);
  const double turned = Eigen::AngleAxisd(end->sample.pose.q).angle() - w * 1.0;
  EXPECT_GE(turned, w * w / (2 * B) - 1e-9);
  EXPECT_LE(turned, kMarginFactor * w * w / (2 * B));
  EXPECT_EQ(end->sample.velocity.angular.norm(), 0.0);
  EXPECT_EQ(end->sample.pose.p.norm(), 0.0);
  const auto peaks = peakAccelerations(p, tc, rest + kSecond);
  EXPECT_LE(peaks.second, B * kBoundSlack);
  EXPECT_EQ(peaks.first, 0.0);
}

TEST(Playback, AMotionEndingDuringTheStopEndsThereAtRest)
{
  Playback p;
  p.play(line(0.0, 1.0, 0.0, 0.0, 2.05), 0, 0);
  // Stopping from 1 m/s at 1 m/s² needs ~0.5 m; the motion ends after 0.05 m.
  const Nanoseconds rest = p.stop(2 * kSecond, bounds(1.0, 0.0));
  EXPECT_LE(rest, 2 * kSecond + kSecond / 10);
  const auto end = p.at(rest);
  EXPECT_FALSE(end->moving);
  EXPECT_NEAR(end->sample.pose.p.x(), 2.05, 1e-9);
}

// A circle at w = 3 (centripetal 9 m/s²) stopped with a bound of 1 m/s²: the motion itself
// exceeds the bound, the stop still ends, at rest on the circle. One turn per loop (2π/w), so that
// the looping motion itself is continuous.
TEST(Playback, AMotionBeyondTheBoundsStillStopsOnItsPath)
{
  Playback p;
  p.setLoop(true);
  const double w = 3.0;
  p.play(circle(w, 2.0 * M_PI / w), 0, 0);
  const Nanoseconds tc = 5 * kSecond;
  const Nanoseconds rest = p.stop(tc, bounds(1.0, 0.0));
  EXPECT_GT(rest, tc);
  EXPECT_LT(rest, tc + 100 * kSecond);
  const auto end = p.at(rest);
  EXPECT_FALSE(end->moving);
  EXPECT_EQ(end->sample.velocity.linear.norm(), 0.0);
  EXPECT_NEAR(end->sample.pose.p.norm(), 1.0, 1e-12);
  // Velocity continuous: no jump between consecutive 0.1 ms samples beyond w² × 0.1 ms.
  for (Nanoseconds t = tc; t < rest; t += kFiniteDifferenceStep)
    EXPECT_LE((p.at(t + kFiniteDifferenceStep)->sample.velocity.linear - p.at(t)->sample.velocity.linear).norm(),
              (w * w + 1.0) * 1e-4 * 1.01)
        << t;
}

// Cancel, then abort while still stopping: the second stop brakes the first one's motion.
TEST(Playback, StoppingAStopEndsNoLaterAndWithinTheBound)
{
  Playback p;
  const double v = 1.0, A = 1.0;
  p.play(line(0.0, v, 0.0, 0.0, 100.0), 0, 0);
  const Nanoseconds first = p.stop(kSecond, bounds(A, 0.0));
  const Nanoseconds tc = kSecond + kSecond / 4;
  const auto before = p.at(tc);
  const Nanoseconds second = p.stop(tc, bounds(A, 0.0));
  EXPECT_LE(second, first);
  EXPECT_NEAR((p.at(tc)->sample.velocity.linear - before->sample.velocity.linear).norm(), 0.0, 1e-12);
  EXPECT_LE(peakAccelerations(p, tc, second + kSecond).first, A * kBoundSlack);
  EXPECT_FALSE(p.at(second)->moving);
}

TEST(Playback, TheTagSurvivesHoldAndStop)
{
  Playback p;
  Motion goal = line(0.0, 1.0, 0.0, 0.0, 100.0);
  goal.tag = "goal 3";
  p.play(goal, 0, 0);
  EXPECT_EQ(p.at(kSecond)->tag, "goal 3");
  const Nanoseconds rest = p.stop(2 * kSecond, bounds(1.0, 1.0));
  EXPECT_EQ(p.at(2 * kSecond + kSecond / 10)->tag, "goal 3");  // stopping
  EXPECT_TRUE(p.at(2 * kSecond + kSecond / 10)->moving);
  EXPECT_EQ(p.at(rest + kSecond)->tag, "goal 3");  // held after the stop
  EXPECT_EQ(p.planStop(rest + kSecond, bounds(1.0, 1.0))->state.tag, "goal 3");
  p.hold(rest + 2 * kSecond);
  EXPECT_EQ(p.at(rest + 3 * kSecond)->tag, "goal 3");

  Motion service = line(0.0, 1.0, 0.0, 0.0, 100.0);
  service.tag = "service";
  p.play(service, 10 * kSecond, 10 * kSecond);
  EXPECT_EQ(p.at(11 * kSecond)->tag, "service");
  p.hold(12 * kSecond);
  EXPECT_EQ(p.at(13 * kSecond)->tag, "service");
  p.stop(14 * kSecond, 1.0);
  EXPECT_EQ(p.at(20 * kSecond)->tag, "service");
  p.play(line(0.0, 1.0, 0.0, 0.0, 1.0), 30 * kSecond, 30 * kSecond);
  EXPECT_EQ(p.at(31 * kSecond)->tag, "");
}

TEST(Playback, PlanStopChangesNothingAndTellsWhereTheStopRests)
{
  Playback p;
  const Motion original = circle(1.0, 100.0);
  p.play(original, 0, 0);
  EXPECT_FALSE(Playback().planStop(0, bounds(1.0, 1.0)).has_value());
  const Nanoseconds tc = 2 * kSecond;
  const StopLimits limits = bounds(0.5, 0.8);
  const std::optional<StopPlan> plan = p.planStop(tc, limits);
  ASSERT_TRUE(plan);
  // Nothing changed: the motion still plays past the planned rest.
  const Nanoseconds later = plan->rest + kSecond;
  EXPECT_TRUE(p.at(later)->moving);
  EXPECT_NEAR(p.at(later)->sample.time, secondsBetween(0, later), 1e-12);
  EXPECT_FALSE(plan->state.moving);
  EXPECT_EQ(plan->state.child_frame_id, "tool");
  // The rest pose is on the path, at the reported τ.
  EXPECT_LT((plan->state.sample.pose.p - original.state_at(plan->state.sample.time).pose.p).norm(), 1e-12);
  EXPECT_GT(plan->state.sample.time, 2.0);

  EXPECT_EQ(p.stop(tc, limits), plan->rest);
  for (Nanoseconds t : { plan->rest, plan->rest + 5 * kSecond })
  {
    const auto held = p.at(t);
    EXPECT_FALSE(held->moving);
    EXPECT_EQ((held->sample.pose.p - plan->state.sample.pose.p).norm(), 0.0);
    EXPECT_EQ(held->sample.pose.q.angularDistance(plan->state.sample.pose.q), 0.0);
    EXPECT_EQ(held->sample.time, plan->state.sample.time);
  }
  EXPECT_TRUE(p.at(plan->rest - kSecond / 100)->moving);
}

// Neither bound set: the smooth ramp of stop_time, as stop(now, ramp_seconds).
TEST(Playback, UnboundedStopKeepsTheSmoothRamp)
{
  Playback p;
  const double v = 0.8, T = 0.5;
  p.play(line(0.0, v, 0.0, 0.0, 100.0), 0, 0);
  const Nanoseconds tc = 2 * kSecond;
  StopLimits limits;
  limits.stop_time = T;
  EXPECT_EQ(p.stop(tc, limits), tc + kSecond / 2);
  for (int k = 0; k <= 20; ++k)
  {
    const double sigma = k / 20.0;
    const auto s = p.at(tc + toNanoseconds(sigma * T));
    EXPECT_NEAR(s->sample.pose.p.x(), 2.0 * v + v * T * (sigma - std::pow(sigma, 3) + 0.5 * std::pow(sigma, 4)), 1e-9);
    EXPECT_NEAR(s->sample.velocity.linear.x(), v * (1 - 3 * sigma * sigma + 2 * std::pow(sigma, 3)), 1e-9);
  }
}

TEST(Playback, StopLimitsAreChecked)
{
  Playback p;
  p.play(line(0.0, 1.0, 0.0, 0.0, 10.0), 0, 0);
  for (double bad : { -1.0, std::nan(""), std::numeric_limits<double>::infinity() })
  {
    EXPECT_THROW(p.stop(kSecond, bounds(bad, 1.0)), std::invalid_argument) << bad;
    EXPECT_THROW(p.stop(kSecond, bounds(1.0, bad)), std::invalid_argument) << bad;
    EXPECT_THROW(p.planStop(kSecond, bounds(bad, 0.0)), std::invalid_argument) << bad;
  }
  StopLimits no_time = bounds(0.0, 0.0);
  no_time.stop_time = 0.0;
  EXPECT_THROW(p.stop(kSecond, no_time), std::invalid_argument);
  no_time.max_linear_acceleration = 1.0;  // bounded: stop_time unused
  EXPECT_NO_THROW(p.stop(kSecond, no_time));
}

// A motion accelerating at the bound: the stop reverses its acceleration, within the bound. The
// motion's speed grows along the path the stop still covers (to ~1.6 m/s), and the law's rate
// plateau is scaled for it from the start speed by the search's factors (stop_law.h): the stop
// takes longer than 1.01/A (2.57 s), within 3 times.
TEST(Playback, AMotionAcceleratingAtTheBoundIsBrakedWithinIt)
{
  Playback p;
  const double A = 1.0;
  p.play(line(0.0, 0.01, A, 0.0, 100.0), 0, 0);
  const Nanoseconds tc = kSecond;  // 1.01 m/s, accelerating at A
  const Nanoseconds rest = p.stop(tc, bounds(A, 0.0));
  EXPECT_LE(secondsBetween(tc, rest), 3.0 * 1.01 / A);
  EXPECT_LE(peakAccelerations(p, tc, rest + kSecond).first, A * kBoundSlack);
}

TEST(Playback, ReadersAndWritersOnSeveralThreads)
{
  Playback p;
  p.play(line(0.0, 1.0, 0.0, 0.0, 1.0), 0, 0);
  std::thread reader([&] {
    for (int i = 0; i < 20000; ++i)
    {
      const auto s = p.at(i * Nanoseconds(1000));
      ASSERT_TRUE(s);
      ASSERT_TRUE(std::isfinite(s->sample.pose.p.x()));
      if (i % 1000 == 0)
      {
        ASSERT_TRUE(p.planStop(i * Nanoseconds(1000), bounds(1.0, 1.0)));
      }
    }
  });
  for (int i = 0; i < 2000; ++i)
  {
    p.play(line(i, 1.0, 0.0, 0.0, 1.0), i * Nanoseconds(10000), i * Nanoseconds(10000));
    if (i % 100 == 0)
      p.stop(i * Nanoseconds(10000), 0.1);
    else if (i % 100 == 50)
      p.stop(i * Nanoseconds(10000), bounds(1.0, 1.0));
  }
  reader.join();
}
