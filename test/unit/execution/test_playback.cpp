// Playback (execution/playback.h), without ROS: the clock in integer nanoseconds, holding before
// and after a motion, looping, splicing a replan at its start, hold, and the stop ramp, each
// against motions written here in closed form (a line at constant acceleration, a circle).
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
    }
  });
  for (int i = 0; i < 2000; ++i)
  {
    p.play(line(i, 1.0, 0.0, 0.0, 1.0), i * Nanoseconds(10000), i * Nanoseconds(10000));
    if (i % 100 == 0)
      p.stop(i * Nanoseconds(10000), 0.1);
  }
  reader.join();
}
