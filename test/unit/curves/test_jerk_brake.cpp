// The jerk-limited stop of a start state (curves/jerk_brake.h): the one-axis stop against the
// closed-form double S from rest acceleration (Biagiotti & Melchiorri §3.4) and constant
// deceleration without a jerk bound, its bounds and its end at rest by finite differences, the
// reversing case near the end of a braking motion, and the vector brake's start state, end at
// rest and translation norms within the bounds for both designs.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "se3_interpolation/curves/jerk_brake.h"
#include "se3_interpolation/timing/jerk_limited.h"

namespace se3_interpolation
{
namespace
{
/// Velocity, acceleration and jerk of a JerkStop at τ by its exact third-order jet.
std::array<double, 4> stateAt(const JerkStop& s, double tau, Side side = Side::kRight)
{
  const Jet<3> p = s.positionAt(Jet<3>::variable(tau), side);
  return { p.coefficient(0), p.coefficient(1), 2.0 * p.coefficient(2), 6.0 * p.coefficient(3) };
}

/// The rest-to-rest double S's stop time from speed v with zero acceleration (§3.4).
double doubleSStop(double v, double a, double j)
{
  return v >= a * a / j ? v / a + a / j : 2.0 * std::sqrt(v / j);
}

TEST(JerkStop, FromZeroAccelerationIsTheDoubleS)
{
  for (double v : { 0.01, 0.2, 1.0, 5.0 })
    for (double a : { 0.5, 2.0 })
      for (double j : { 1.0, 20.0 })
      {
        const JerkStop s(v, 0.0, a, j);
        EXPECT_NEAR(s.stopTime(), doubleSStop(v, a, j), 1e-12 * doubleSStop(v, a, j)) << v << " " << a << " " << j;
      }
}

TEST(JerkStop, WithoutAJerkBoundDeceleratesAtTheBound)
{
  const JerkStop s(1.5, 0.7, 2.0, 0.0);
  EXPECT_DOUBLE_EQ(s.stopTime(), 0.75);
  EXPECT_DOUBLE_EQ(s.stopPosition(), 1.5 * 1.5 / 4.0);
  const auto x = stateAt(s, 0.3);
  EXPECT_DOUBLE_EQ(x[2], -2.0);
}

TEST(JerkStop, RandomStartsEndAtRestWithinTheBounds)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial)
  {
    const double a_max = 0.1 + 3.0 * u(rng);
    const double j_max = 0.5 + 50.0 * u(rng);
    const double v0 = 2.0 * u(rng) * u(rng);
    const double a0 = (2.0 * u(rng) - 1.0) * a_max;  // within the bound, either sign
    const JerkStop s(v0, a0, a_max, j_max);
    SCOPED_TRACE(std::to_string(v0) + " " + std::to_string(a0) + " " + std::to_string(a_max) + " " +
                 std::to_string(j_max));
    const double T = s.stopTime();
    ASSERT_TRUE(std::isfinite(T));
    const auto start = stateAt(s, 0.0);
    EXPECT_NEAR(start[1], v0, 1e-12);
    EXPECT_NEAR(start[2], a0, 1e-12);
    const auto end = stateAt(s, T, Side::kLeft);
    EXPECT_NEAR(end[1], 0.0, 1e-9 * (1.0 + v0));
    EXPECT_NEAR(end[2], 0.0, 1e-9 * (1.0 + a_max));
    for (int k = 0; k <= 200; ++k)
    {
      const auto x = stateAt(s, T * k / 200.0);
      EXPECT_LE(std::abs(x[2]), a_max * (1.0 + 1e-12)) << k;
      EXPECT_LE(std::abs(x[3]), j_max * (1.0 + 1e-12)) << k;
    }
    // Finite differences of the position agree with the jet's velocity (continuity of the pieces).
    const double h = 1e-6 * std::max(T, 1e-3);
    for (int k = 1; k < 20; ++k)
    {
      const double t = T * k / 20.0;
      const double fd = (s.positionAt(t + h, Side::kRight) - s.positionAt(t - h, Side::kRight)) / (2.0 * h);
      EXPECT_NEAR(fd, stateAt(s, t)[1], 1e-5 * (1.0 + v0));
    }
  }
}

// Near the end of a braking motion at jerk 10 (speed 5e-6, braking at 0.01) the state lies on the
// double S's last ramp: the stop is that ramp, 1 ms. With less speed left (1e-6), ramping the braking
// to zero would reverse the motion, so the acceleration passes zero and comes back: it goes back a
// little and ends at rest.
TEST(JerkStop, NearlySpentBrakingEndsOnItsRampOrReversesBriefly)
{
  const JerkStop on_ramp(5e-6, -0.01, 1.0, 10.0);
  EXPECT_NEAR(on_ramp.stopTime(), 1e-3, 1e-12);
  const JerkStop reversing(1e-6, -0.01, 1.0, 10.0);
  // The acceleration rises from −0.01 through zero to a_p = sqrt(a0²/2 − J v0) and back (S2):
  // T = (|a0| + 2 a_p) / J.
  const double peak = std::sqrt(0.5 * 0.01 * 0.01 - 10.0 * 1e-6);
  EXPECT_NEAR(reversing.stopTime(), (0.01 + 2.0 * peak) / 10.0, 1e-15);
  double lowest_speed = 0.0;
  for (int k = 0; k <= 100; ++k)
    lowest_speed = std::min(lowest_speed, stateAt(reversing, reversing.stopTime() * k / 100.0)[1]);
  EXPECT_LT(lowest_speed, 0.0);
  for (const JerkStop* s : { &on_ramp, &reversing })
  {
    const auto end = stateAt(*s, s->stopTime(), Side::kLeft);
    EXPECT_NEAR(end[1], 0.0, 1e-15);
    EXPECT_NEAR(end[2], 0.0, 1e-12);
    EXPECT_LT(std::abs(s->stopPosition()), 1e-8);
  }
}

Twist twist(const Eigen::Vector3d& l, const Eigen::Vector3d& a)
{
  Twist t;
  t.linear = l;
  t.angular = a;
  return t;
}

TEST(JerkBrake, StartsInTheStateEndsAtRestTranslationWithinTheBounds)
{
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  const std::array<double, 2> a_max = { 2.0, 4.0 };
  const std::array<double, 2> j_max = { 20.0, 40.0 };
  for (int trial = 0; trial < 200; ++trial)
    for (StopDesign design : { StopDesign::kSplit, StopDesign::kRamp })
    {
      const Pose<double> x0(Quaternion<double>(Eigen::AngleAxisd(n(rng), Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized())),
                            Eigen::Vector3d(n(rng), n(rng), n(rng)));
      Eigen::Vector3d al(n(rng), n(rng), n(rng));
      al *= 1.9 / std::max(1.9, al.norm());
      const Twist v = twist(Eigen::Vector3d(n(rng), n(rng), n(rng)) * 0.4, Eigen::Vector3d(n(rng), n(rng), n(rng)) * 0.4);
      const Twist a = twist(al, Eigen::Vector3d(n(rng), n(rng), n(rng)) * 0.5);
      const JerkBrake b = makeJerkBrake(x0, v, a, a_max, j_max, 1.0, 1.0, { design, design });
      const double T = b.stopTime();
      ASSERT_GT(T, 0.0);
      const timing::Kinematics3 k0 = timing::kinematics3FromJet(b.at(Jet<3>::variable(0.0), Side::kRight));
      EXPECT_LT((k0.velocity.linear - v.linear).norm(), 1e-12);
      EXPECT_LT((k0.velocity.angular - v.angular).norm(), 1e-12);
      EXPECT_LT((k0.acceleration.linear - a.linear).norm(), 1e-12);
      EXPECT_LT((k0.acceleration.angular - a.angular).norm(), 1e-12);
      const timing::Kinematics3 k1 = timing::kinematics3FromJet(b.at(Jet<3>::variable(T), Side::kLeft));
      EXPECT_LT(k1.velocity.linear.norm() + k1.velocity.angular.norm(), 1e-9);
      EXPECT_LT(k1.acceleration.linear.norm() + k1.acceleration.angular.norm(), 1e-9);
      const timing::Kinematics3 after = timing::kinematics3FromJet(b.at(Jet<3>::variable(T * 1.5), Side::kRight));
      EXPECT_EQ(after.velocity.linear.norm() + after.velocity.angular.norm(), 0.0);
      // The translation is exact in its axes: its norms hold the bounds (the split design's share
      // of the acceleration bound is 1 here, so only the ramp design and the jerk are guaranteed).
      for (int s = 0; s <= 400; ++s)
      {
        const timing::Kinematics3 k = timing::kinematics3FromJet(b.at(Jet<3>::variable(T * s / 400.0), Side::kRight));
        EXPECT_LE(k.jerk.linear.norm(), j_max[0] * (1.0 + 1e-9));
        if (design == StopDesign::kRamp)
          EXPECT_LE(k.acceleration.linear.norm(), a_max[0] * (1.0 + 1e-9));
      }
    }
}

// A rotation about one fixed axis with velocity and acceleration along it is the one-axis stop.
TEST(JerkBrake, RotationAboutOneAxisIsTheOneAxisStop)
{
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();
  const Pose<double> x0(Quaternion<double>(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())), Eigen::Vector3d::Zero());
  const JerkBrake b = makeJerkBrake(x0, twist(Eigen::Vector3d::Zero(), 1.2 * axis),
                                    twist(Eigen::Vector3d::Zero(), -0.5 * axis), { 2.0, 3.0 }, { 20.0, 15.0 }, 1.0, 1.0,
                                    { StopDesign::kSplit, StopDesign::kSplit });
  const JerkStop s(1.2, -0.5, 3.0, 15.0);
  EXPECT_NEAR(b.stopTime(), s.stopTime(), 1e-15);
  for (int k = 0; k <= 50; ++k)
  {
    const double t = s.stopTime() * k / 50.0;
    const Quaternion<double> expected = Quaternion<double>(Eigen::AngleAxisd(s.positionAt(t, Side::kRight), axis)) * x0.q;
    EXPECT_LT(b.at(t, Side::kRight).q.angularDistance(expected), 1e-12) << t;
  }
}
}  // namespace
}  // namespace se3_interpolation
