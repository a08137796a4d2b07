// Replanning from a moving state (planner.h StartState, curves/start_join.h, the time-optimal
// start speed): the trajectory starts in the given state (C² switch), checked against finite
// differences of the produced curve, the classical quintic Hermite polynomial in the abelian cases,
// a closed-form time-optimal line motion, and hard points (rest, rotations near pi, q vs -q).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "se3_interpolation/curves/start_join.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "test_utils.h"

namespace se3_interpolation
{
namespace
{
constexpr double kSwitchTolerance = 1e-9;  // the C² switch tolerance of docs/timing.md

Twist twist(const Eigen::Vector3d& linear, const Eigen::Vector3d& angular)
{
  Twist t;
  t.linear = linear;
  t.angular = angular;
  return t;
}

Pose<double> pose(const Eigen::Vector3d& p, double angle, const Eigen::Vector3d& axis)
{
  return Pose<double>(Quaternion<double>(Eigen::AngleAxisd(angle, axis.normalized())), p);
}

StartState movingState()
{
  StartState s;
  s.pose = pose({ 0.3, -0.2, 0.5 }, 0.7, { 1.0, 2.0, -0.5 });
  s.velocity = twist({ 0.4, 0.1, -0.3 }, { 0.2, -0.5, 0.3 });
  s.acceleration = twist({ -0.6, 0.2, 0.1 }, { 0.4, 0.1, -0.7 });
  return s;
}

TrajectoryRequest requestFrom(const StartState& s, const std::string& curve, const std::string& geometry)
{
  TrajectoryRequest r;
  r.waypoints = { pose({ 1.0, 0.0, 0.5 }, 1.2, { 0.0, 0.0, 1.0 }), pose({ 1.5, 1.0, 0.2 }, 0.4, { 1.0, 0.0, 0.0 }),
                  pose({ 0.5, 1.5, 0.0 }, -0.6, { 0.0, 1.0, 1.0 }) };
  r.curve = curve;
  r.geometry = geometry;
  r.duration = 4.0;
  r.start_state = s;
  return r;
}

double rotationBetween(const Quaternion<double>& a, const Quaternion<double>& b)
{
  return rotationAngle(Quaternion<double>(a.conjugate() * b));
}

/// The first sample (exact jets) and finite differences of point_at at 0 against the start state.
void expectStartsIn(const TrajectoryResult& out, const StartState& s, double fd_tolerance)
{
  ASSERT_FALSE(out.samples.empty());
  const TrajectorySample& first = out.samples.front();
  EXPECT_EQ(first.time, 0.0);
  EXPECT_LT((first.pose.p - s.pose.p).norm(), kSwitchTolerance);
  EXPECT_LT(rotationBetween(first.pose.q, s.pose.q), kSwitchTolerance);
  EXPECT_LT((first.velocity.linear - s.velocity.linear).norm(), kSwitchTolerance);
  EXPECT_LT((first.velocity.angular - s.velocity.angular).norm(), kSwitchTolerance);
  EXPECT_LT((first.acceleration.linear - s.acceleration.linear).norm(), kSwitchTolerance);
  EXPECT_LT((first.acceleration.angular - s.acceleration.angular).norm(), kSwitchTolerance);
  // Independent of the jets: differences of the curve's values (the joining polynomial extends
  // analytically to t < 0).
  const Kinematics fd = test::centralDifferences(out.point_at, 0.0, 1e-3);
  EXPECT_LT((fd.velocity.linear - s.velocity.linear).norm(), fd_tolerance);
  EXPECT_LT((fd.velocity.angular - s.velocity.angular).norm(), fd_tolerance);
  EXPECT_LT((fd.acceleration.linear - s.acceleration.linear).norm(), fd_tolerance);
  EXPECT_LT((fd.acceleration.angular - s.acceleration.angular).norm(), fd_tolerance);
}

TEST(StartJoin, PoseJetIsTheInverseOfKinematicsFromJet)
{
  const StartState s = movingState();
  const Kinematics k = kinematicsFromJet(poseJet(s.pose, s.velocity, s.acceleration));
  EXPECT_LT((k.velocity.linear - s.velocity.linear).norm(), 1e-15);
  EXPECT_LT((k.velocity.angular - s.velocity.angular).norm(), 1e-15);
  EXPECT_LT((k.acceleration.linear - s.acceleration.linear).norm(), 1e-15);
  EXPECT_LT((k.acceleration.angular - s.acceleration.angular).norm(), 1e-15);
}

// Every curve family, both SE(3) geometries: C² switch, and the first requested waypoint reached.
TEST(StartJoin, EveryCurveStartsInTheGivenState)
{
  for (const char* geometry : { "double_geodesic", "screw" })
    for (const char* curve : { "piecewise_geodesic", "bezier", "bspline", "interpolating", "hermite", "blended" })
    {
      SCOPED_TRACE(std::string(curve) + " / " + geometry);
      const TrajectoryResult out = generate(requestFrom(movingState(), curve, geometry), test::unhurriedLimits());
      expectStartsIn(out, movingState(), 1e-5);
      ASSERT_EQ(out.waypoint_times.size(), 3u);
      EXPECT_GT(out.waypoint_times.front(), 0.0);
      EXPECT_NEAR(out.samples.back().time, 4.0, 1e-12);
    }
}

TEST(StartJoin, InterpolatingStartTakesTheStateNatively)
{
  const StartState s = movingState();
  TrajectoryRequest r = requestFrom(s, "interpolating", "screw");
  r.end_condition = "start";
  r.times = { 1.0, 2.0, 3.0 };
  r.start_velocity = twist({ 9.0, 9.0, 9.0 }, { 0.0, 0.0, 0.0 });  // replaced by the start state
  const TrajectoryResult out = generate(r, test::unhurriedLimits());
  expectStartsIn(out, s, 1e-5);
  // Natively: the same curve as the forward spline through the start pose and the waypoints with
  // the state as its start data (no joining segment).
  TrajectoryRequest plain = r;
  plain.start_state.reset();
  plain.waypoints.insert(plain.waypoints.begin(), s.pose);
  plain.times.insert(plain.times.begin(), 0.0);
  plain.start_velocity = s.velocity;
  plain.start_acceleration = s.acceleration;
  const TrajectoryResult ref = generate(plain, test::unhurriedLimits());
  ASSERT_EQ(out.samples.size(), ref.samples.size());
  for (std::size_t i = 0; i < out.samples.size(); ++i)
    EXPECT_LT(test::poseDistance(out.samples[i].pose, ref.samples[i].pose), 1e-12);
}

// Interpolating curves pass the waypoints at their times, which count from the switch.
TEST(StartJoin, TimesCountFromTheSwitch)
{
  TrajectoryRequest r = requestFrom(movingState(), "interpolating", "double_geodesic");
  r.times = { 1.0, 2.5, 3.0 };
  const TrajectoryResult out = generate(r, test::unhurriedLimits());
  ASSERT_EQ(out.waypoint_times.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i)
  {
    EXPECT_DOUBLE_EQ(out.waypoint_times[i], r.times[i]);
    EXPECT_LT(test::poseDistance(out.point_at(r.times[i]), r.waypoints[i]), 1e-9);
  }
  expectStartsIn(out, movingState(), 1e-5);
}

// At the joint the joining segment and the curve agree to second order (one-sided jets).
TEST(StartJoin, JointIsC2)
{
  const StartState s = movingState();
  for (double angle : { 0.3, 2.0, M_PI - 1e-6 })
  {
    SCOPED_TRACE(angle);
    std::vector<Pose<double>> points{ pose({ 1.0, 0.0, 0.0 }, 0.7 + angle, { 1.0, 2.0, -0.5 }),
                                      pose({ 2.0, 1.0, 0.0 }, 0.2, { 0.0, 0.0, 1.0 }) };
    auto rest = std::make_shared<PiecewiseGeodesic<ScrewSe3>>(points, std::vector<double>{ 0.0, 2.0 });
    StartJoinedCurve<ScrewSe3> c(s.pose, poseJet(s.pose, s.velocity, s.acceleration), 0.0, 1.5, rest, 0.0);
    const Kinematics left = kinematicsAt(c, 1.5, Side::kLeft);
    const Kinematics right = kinematicsAt(c, 1.5, Side::kRight);
    const Kinematics ref = kinematicsAt(*rest, 0.0);
    EXPECT_LT(test::poseDistance(left.pose, ref.pose), 1e-9);
    EXPECT_LT(test::poseDistance(right.pose, ref.pose), 1e-12);
    const double scale = 1.0 + ref.velocity.angular.norm() + ref.velocity.linear.norm();
    EXPECT_LT((left.velocity.linear - ref.velocity.linear).norm(), 1e-9 * scale);
    EXPECT_LT((left.velocity.angular - ref.velocity.angular).norm(), 1e-9 * scale);
    EXPECT_LT((left.acceleration.linear - ref.acceleration.linear).norm(), 1e-9 * scale * scale);
    EXPECT_LT((left.acceleration.angular - ref.acceleration.angular).norm(), 1e-9 * scale * scale);
    EXPECT_NEAR(c.endTime(), 3.5, 1e-15);
    EXPECT_LT(test::poseDistance(c.value(3.5), points[1]), 1e-12);
  }
}

/// The classical quintic Hermite interpolant on [0, h] (basis polynomials in u = t/h).
double quinticHermite(double t, double h, double p0, double v0, double a0, double p1, double v1, double a1)
{
  const double u = t / h, u3 = u * u * u, u4 = u3 * u, u5 = u4 * u;
  return (1 - 10 * u3 + 15 * u4 - 6 * u5) * p0 + (u - 6 * u3 + 8 * u4 - 3 * u5) * h * v0 +
         0.5 * (u * u - 3 * u3 + 3 * u4 - u5) * h * h * a0 + 0.5 * (u3 - 2 * u4 + u5) * h * h * a1 +
         (-4 * u3 + 7 * u4 - 3 * u5) * h * v1 + (10 * u3 - 15 * u4 + 6 * u5) * p1;
}

// Pure translation: each coordinate is the classical quintic Hermite polynomial.
TEST(StartJoin, PureTranslationIsTheClassicalQuinticHermite)
{
  StartState s;
  s.pose = pose({ 0.1, 0.2, 0.3 }, 0.4, { 0.0, 1.0, 0.0 });
  s.velocity = twist({ 1.0, -2.0, 0.5 }, Eigen::Vector3d::Zero());
  s.acceleration = twist({ 3.0, 0.5, -1.0 }, Eigen::Vector3d::Zero());
  std::vector<Pose<double>> points{ pose({ 2.0, 1.0, -1.0 }, 0.4, { 0.0, 1.0, 0.0 }),
                                    pose({ 3.0, 3.0, 0.0 }, 0.4, { 0.0, 1.0, 0.0 }) };
  const double h = 1.7;
  for (const bool screw : { false, true })
  {
    std::shared_ptr<const Curve<ScrewSe3>> rest_s =
        std::make_shared<PiecewiseGeodesic<ScrewSe3>>(points, std::vector<double>{ 0.0, 2.0 });
    std::shared_ptr<const Curve<DoubleGeodesicSe3>> rest_d =
        std::make_shared<PiecewiseGeodesic<DoubleGeodesicSe3>>(points, std::vector<double>{ 0.0, 2.0 });
    const Eigen::Vector3d v1 = (points[1].p - points[0].p) / 2.0;  // the geodesic's constant velocity
    for (double t : { 0.0, 0.2, 0.85, 1.3, 1.7 })
    {
      Pose<double> x = screw ? StartJoinedCurve<ScrewSe3>(s.pose, poseJet(s.pose, s.velocity, s.acceleration), 0.0,
                                                          h, rest_s, 0.0)
                                   .value(t)
                             : StartJoinedCurve<DoubleGeodesicSe3>(s.pose, poseJet(s.pose, s.velocity, s.acceleration),
                                                                   0.0, h, rest_d, 0.0)
                                   .value(t);
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(x.p[i],
                    quinticHermite(t, h, s.pose.p[i], s.velocity.linear[i], s.acceleration.linear[i], points[0].p[i],
                                   v1[i], 0.0),
                    1e-12)
            << "t = " << t << ", screw " << screw;
      EXPECT_LT(rotationBetween(x.q, s.pose.q), 1e-12);
    }
  }
}

// Rotation about one fixed axis: the angle is the classical quintic Hermite polynomial, also near
// half a turn and with the start quaternion given as -q.
TEST(StartJoin, RotationAboutOneAxisIsTheClassicalQuinticHermite)
{
  const Eigen::Vector3d axis(0.0, 0.6, 0.8);
  for (double end_angle : { 0.5, 2.9, 0.2 + M_PI - 1e-6 })
    for (double sign : { 1.0, -1.0 })
    {
      StartState s;
      s.pose = pose({ 0.0, 0.0, 0.0 }, 0.2, axis);
      s.pose.q.coeffs() *= sign;
      s.velocity = twist(Eigen::Vector3d::Zero(), 0.8 * axis);
      s.acceleration = twist(Eigen::Vector3d::Zero(), -1.5 * axis);
      std::vector<Pose<double>> points{ pose({ 0.0, 0.0, 0.0 }, end_angle, axis),
                                        pose({ 0.0, 0.0, 0.0 }, end_angle + 1.0, axis) };
      auto rest = std::make_shared<PiecewiseGeodesic<ScrewSe3>>(points, std::vector<double>{ 0.0, 2.0 });
      const double h = 1.3;
      StartJoinedCurve<ScrewSe3> c(s.pose, poseJet(s.pose, s.velocity, s.acceleration), 0.0, h, rest, 0.0);
      for (double t : { 0.0, 0.3, 0.65, 1.0, 1.3 })
      {
        const double theta = quinticHermite(t, h, 0.2, 0.8, -1.5, end_angle, 0.5, 0.0);
        EXPECT_LT(rotationBetween(c.value(t).q, pose({ 0, 0, 0 }, theta, axis).q), 1e-10)
            << "end " << end_angle << " sign " << sign << " t " << t;
      }
    }
}

// q and -q describe the same start: the same trajectory.
TEST(StartJoin, NegatedStartQuaternionGivesTheSameMotion)
{
  StartState a = movingState(), b = movingState();
  b.pose.q.coeffs() = -b.pose.q.coeffs();
  const TrajectoryResult ra = generate(requestFrom(a, "interpolating", "screw"), test::unhurriedLimits());
  const TrajectoryResult rb = generate(requestFrom(b, "interpolating", "screw"), test::unhurriedLimits());
  ASSERT_EQ(ra.samples.size(), rb.samples.size());
  for (std::size_t i = 0; i < ra.samples.size(); ++i)
  {
    EXPECT_LT(test::poseDistance(ra.samples[i].pose, rb.samples[i].pose), 1e-12);
    EXPECT_LT((ra.samples[i].velocity.angular - rb.samples[i].velocity.angular).norm(), 1e-10);
  }
  expectStartsIn(rb, b, 1e-5);
}

// At rest from the held pose when waypoints[0] is that pose: it is not visited twice.
TEST(StartJoin, RestAtTheFirstWaypointStartsThere)
{
  TrajectoryRequest r = requestFrom(StartState(), "interpolating", "double_geodesic");
  r.start_state->pose = r.waypoints[0];
  const TrajectoryResult out = generate(r, test::unhurriedLimits());
  expectStartsIn(out, *r.start_state, 1e-6);
  ASSERT_EQ(out.waypoint_times.size(), 3u);
  EXPECT_EQ(out.waypoint_times[0], 0.0);
  EXPECT_LT(test::poseDistance(out.point_at(out.waypoint_times[2]), r.waypoints[2]), 1e-9);
}

// Corner blends: one radius per requested waypoint, the start's own corner not among them.
TEST(StartJoin, BlendedPolylineListsTheRequestedWaypointsOnly)
{
  TrajectoryRequest r = requestFrom(movingState(), "piecewise_geodesic", "double_geodesic");
  r.blend_radius = 0.1;
  const TrajectoryResult out = generate(r, test::unhurriedLimits());
  expectStartsIn(out, movingState(), 1e-5);
  EXPECT_EQ(out.blend_radii.size(), r.waypoints.size());
  EXPECT_EQ(out.waypoint_times.size(), r.waypoints.size());
}

// The trajectory ends at the last waypoint (the end time maps onto the curve's end, no extrapolation).
TEST(StartJoin, LastSampleIsTheLastWaypointExactly)
{
  for (const char* timing : { "stretch", "time_optimal" })
  {
    SCOPED_TRACE(timing);
    TrajectoryRequest r = requestFrom(movingState(), "piecewise_geodesic", "double_geodesic");
    r.waypoints = { pose({ 0.0, 0.0, 0.0 }, 0.0, { 0, 0, 1 }), pose({ 1.0, 0.0, 0.0 }, 0.0, { 0, 0, 1 }) };
    r.timing = timing;
    // (Stretch from a moving start allows no k > 1: no bounds there.)
    const double bound = std::string(timing) == "stretch" ? 0.0 : 1.0;
    r.max_linear_velocity = bound;
    r.max_linear_acceleration = bound;
    r.max_angular_velocity = bound;
    r.max_angular_acceleration = bound;
    r.start_state->pose.q = Quaternion<double>::Identity();
    r.start_state->velocity.angular.setZero();
    r.start_state->acceleration.angular.setZero();
    for (double s : { 0.1, 0.3, 0.7, 1.1, 1.9 })
    {
      r.start_state->pose.p = Eigen::Vector3d(0.3 * s, -0.2 * s, 0.1);
      const TrajectoryResult out = generate(r, test::unhurriedLimits());
      // (To rounding: the geodesic's lambda = (t - t_i) / h need not round to 1 at the end.)
      EXPECT_NEAR(out.samples.back().pose.p.x(), 1.0, 1e-15) << s;
      EXPECT_NEAR(out.samples.back().pose.p.y(), 0.0, 1e-15) << s;
    }
  }
}

TEST(StartJoin, OneWaypointIsEnough)
{
  TrajectoryRequest r = requestFrom(movingState(), "interpolating", "screw");
  r.waypoints.resize(1);
  const TrajectoryResult out = generate(r, test::unhurriedLimits());
  expectStartsIn(out, movingState(), 1e-5);
  EXPECT_LT(test::poseDistance(out.samples.back().pose, r.waypoints[0]), 1e-9);
}

// A bound that stretches the curve keeps the start state exactly (the joint is rebuilt).
// A moving start fixes stretch's time scale: within the bounds the motion keeps it (k = 1); a
// curve that would need k > 1 is refused naming timing and suggesting time_optimal (a stretch
// would change the start velocity). A start at rest is stretched like any curve.
TEST(StartJoin, StretchFromAMovingStartKeepsItOrIsRefused)
{
  TrajectoryRequest r = requestFrom(movingState(), "interpolating", "double_geodesic");
  r.duration = 4.0;
  r.max_linear_velocity = 100.0;
  TrajectoryResult out = generate(r, test::unhurriedLimits());
  EXPECT_EQ(out.time_scale, 1.0);
  expectStartsIn(out, movingState(), 1e-5);
  r.duration = 1.0;
  r.max_linear_velocity = 1.0;
  try
  {
    generate(r, test::unhurriedLimits());
    ADD_FAILURE() << "a stretch of a moving start was accepted";
  }
  catch (const InvalidInputError& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("timing:", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("time_optimal"), std::string::npos) << e.what();
  }
  StartState rest = movingState();
  rest.velocity = Twist();
  rest.acceleration = Twist();
  r.start_state = rest;
  out = generate(r, test::unhurriedLimits());
  EXPECT_GT(out.time_scale, 1.5);
  expectStartsIn(out, rest, 1e-5);
  EXPECT_NEAR(out.samples.back().time, out.duration, 1e-12);
}

// time_optimal from a moving state: the motion starts exactly in it (exact jets; velocity by
// differences of the poses on both sides of 0: the acceleration may jump just after the switch, as
// it does wherever time-optimal timing switches), passes the waypoints at the reported times, holds
// every bound on a dense evaluation and ends at rest.
TEST(StartJoin, TimeOptimalStartsInTheMovingStateWithinTheBounds)
{
  for (const char* geometry : { "double_geodesic", "screw" })
  {
    SCOPED_TRACE(geometry);
    TrajectoryRequest r = requestFrom(movingState(), "interpolating", geometry);
    r.timing = "time_optimal";
    r.max_linear_velocity = 2.0;
    r.max_angular_velocity = 2.0;
    r.max_linear_acceleration = 3.0;
    r.max_angular_acceleration = 3.0;
    r.sample_count = 2000;
    const TrajectoryResult out = generate(r, test::unhurriedLimits());
    const StartState s = movingState();
    const TrajectorySample& first = out.samples.front();
    EXPECT_LT((first.pose.p - s.pose.p).norm(), kSwitchTolerance);
    EXPECT_LT((first.velocity.linear - s.velocity.linear).norm(), kSwitchTolerance);
    EXPECT_LT((first.velocity.angular - s.velocity.angular).norm(), kSwitchTolerance);
    EXPECT_LT((first.acceleration.linear - s.acceleration.linear).norm(), kSwitchTolerance);
    EXPECT_LT((first.acceleration.angular - s.acceleration.angular).norm(), kSwitchTolerance);
    const Kinematics fd = test::centralDifferences(out.point_at, 0.0, 1e-6);
    EXPECT_LT((fd.velocity.linear - s.velocity.linear).norm(), 1e-5);
    EXPECT_LT((fd.velocity.angular - s.velocity.angular).norm(), 1e-5);
    EXPECT_EQ(out.recovery_time, 0.0);
    for (std::size_t i = 0; i < r.waypoints.size(); ++i)
      EXPECT_LT(test::poseDistance(out.point_at(out.waypoint_times[i]), r.waypoints[i]), 1e-9) << i;
    for (int k = 0; k <= 20000; ++k)
    {
      const TrajectorySample x = out.state_at(out.duration * k / 20000.0);
      EXPECT_LE(x.velocity.linear.norm(), 2.0 * (1.0 + 1e-6)) << x.time;
      EXPECT_LE(x.velocity.angular.norm(), 2.0 * (1.0 + 1e-6)) << x.time;
      EXPECT_LE(x.acceleration.linear.norm(), 3.0 * (1.0 + 1e-6)) << x.time;
      EXPECT_LE(x.acceleration.angular.norm(), 3.0 * (1.0 + 1e-6)) << x.time;
    }
    EXPECT_LT(out.samples.back().velocity.linear.norm(), 1e-6);
  }
}

// A rate at its bound at a grid point of the time-optimal timing can rise into the interval and
// fall back before its middle, where the parabola through the interval's ends and middle peaks at
// its end: the request-space grid's case (interpolating, clamped, screw, two waypoints, only
// max_angular_acceleration, from a moving start) reached 0.8079 rad/s² against 0.8 at t = 0.853 s
// and reported 0.8 (time_optimal_solver.h, kQuarterFloor: a motion from a moving start is checked
// at the quarters too). Measured here on 2·10⁵ states and by central differences of the angular
// velocity around the peak; the figure must be the measured peak.
TEST(StartJoin, TimeOptimalFromAMovingStartHoldsTheBoundBetweenTheCheckedPoints)
{
  TrajectoryRequest r;
  r.waypoints = { Pose<double>(Quaternion<double>(0.82582406459599578, 0.17251512573128769, -0.50342962866468843,
                                                  0.18657908433316051),
                               Eigen::Vector3d(1.0321243413931693, -0.16462585364415006, 1.3440602088887645)),
                  Pose<double>(Quaternion<double>(-0.21926715463381077, -0.35799638087216579, -0.15171323389255953,
                                                  0.89484277995806916),
                               Eigen::Vector3d(1.1013362493491887, 0.19760539971676644, 0.29629445328473936)) };
  r.curve = "interpolating";
  r.geometry = "screw";
  r.end_condition = "clamped";
  r.start_velocity = twist({ -0.15666096766249824, 0.068466047960707085, 0.03967790321985222 },
                           { 0.30148320567182263, -0.0092131345471802763, -0.24393181316986834 });
  r.end_velocity = twist({ -0.2156190476444626, 0.28433932993056543, -0.28443516106612082 },
                         { 0.18398480397722139, 0.081532899007089904, 0.011905843896666622 });
  r.timing = "time_optimal";
  r.max_angular_acceleration = 0.8;
  r.sample_count = 64;
  StartState s;
  s.pose = Pose<double>(Quaternion<double>(0.7308271314684075, 0.19722074629737862, -0.60387851538240622,
                                           0.24965259822221963),
                        Eigen::Vector3d(0.73199262184071534, -0.078073822530450754, 1.1380755084166654));
  s.velocity = twist({ 0.12, -0.05, 0.04 }, { 0.05, 0.1, -0.08 });
  s.acceleration = twist({ -0.1, 0.05, 0.1 }, { 0.1, -0.1, 0.05 });
  r.start_state = s;
  const TrajectoryResult out = generate(r, test::unhurriedLimits());
  constexpr int kStates = 200000;
  double peak = 0.0, peak_time = 0.0;
  for (int k = 0; k <= kStates; ++k)
  {
    const TrajectorySample x = out.state_at(out.duration * k / kStates);
    if (x.acceleration.angular.norm() > peak)
    {
      peak = x.acceleration.angular.norm();
      peak_time = x.time;
    }
  }
  EXPECT_LE(peak, 0.8 * (1.0 + 1e-6)) << "at t = " << peak_time;
  EXPECT_NEAR(out.figures.max_angular_acceleration, peak, 1e-6 * 0.8);
  // Central differences of the angular velocity on both sides of the peak (h = 1e-5 s).
  for (double t : { peak_time - 1e-3, peak_time, peak_time + 1e-3 })
  {
    const double h = 1e-5, at = std::min(std::max(t, h), out.duration - h);
    const Eigen::Vector3d difference =
        (out.state_at(at + h).velocity.angular - out.state_at(at - h).velocity.angular) / (2.0 * h);
    EXPECT_LE(difference.norm(), 0.8 * (1.0 + 1e-5)) << "at t = " << at;
  }
}

TEST(StartJoin, TimeOptimalAtRestStartsAtRest)
{
  TrajectoryRequest r = requestFrom(StartState(), "interpolating", "screw");
  r.start_state->pose = pose({ -1.0, 0.0, 0.0 }, 0.0, { 0.0, 0.0, 1.0 });
  r.timing = "time_optimal";
  r.max_linear_velocity = 1.0;
  r.max_angular_velocity = 1.0;
  r.max_linear_acceleration = 2.0;
  r.max_angular_acceleration = 2.0;
  const TrajectoryResult out = generate(r, test::unhurriedLimits());
  EXPECT_LT(test::poseDistance(out.samples.front().pose, r.start_state->pose), 1e-12);
  EXPECT_LT(out.samples.front().velocity.linear.norm() + out.samples.front().velocity.angular.norm(), 1e-12);
}

// Time-optimal along a straight line from speed v0: accelerate to v_max, cruise, brake to rest
// (closed form), and the profile's first speed is v0. A start at 3 v_max recovers by braking at
// a_max: its recovery ends at (3 v_max − v_max) / a_max, over which the speed never rises, and the
// duration is the closed form's (brake to v_max, cruise, brake to rest).
TEST(StartJoin, TimeOptimalLineFromAMovingStartMatchesTheClosedForm)
{
  const double length = 4.0, v0 = 0.5, vmax = 1.0, amax = 2.0, path_duration = 8.0;
  std::vector<Pose<double>> points{ pose({ 0, 0, 0 }, 0.0, { 0, 0, 1 }), pose({ length, 0, 0 }, 0.0, { 0, 0, 1 }) };
  auto line = std::make_shared<PiecewiseGeodesic<DoubleGeodesicSe3>>(points, std::vector<double>{ 0.0, path_duration });
  timing::RateBounds bounds;
  bounds.velocity = { vmax, 0.0 };
  bounds.acceleration = { amax, 0.0 };
  timing::TimeOptimalOptions options;
  const double path_rate = length / path_duration;  // |C'|
  options.start_speed = v0 / path_rate;
  const timing::TimingProfile p = timing::timeOptimalProfile(timing::CurvePath<DoubleGeodesicSe3>(line), bounds, options);
  const double up = (vmax - v0) / amax, down = vmax / amax;
  const double cruise = (length - (vmax * vmax - v0 * v0) / (2 * amax) - vmax * vmax / (2 * amax)) / vmax;
  EXPECT_NEAR(p.duration(), up + cruise + down, 2e-3 * (up + cruise + down));
  EXPECT_NEAR(std::sqrt(p.x.front()) * p.stretch * path_rate, v0, 1e-12);
  EXPECT_EQ(p.stretch, 1.0);
  EXPECT_EQ(p.recovery_end, p.t.front());
  EXPECT_EQ(p.x.back(), 0.0);
  const double v_fast = 3.0 * vmax;
  options.start_speed = v_fast / path_rate;
  const timing::TimingProfile q = timing::timeOptimalProfile(timing::CurvePath<DoubleGeodesicSe3>(line), bounds, options);
  EXPECT_EQ(std::sqrt(q.x.front()) * path_rate, v_fast);
  const double recovery = (v_fast - vmax) / amax;
  EXPECT_NEAR(q.recovery_end - q.t.front(), recovery, 2e-2 * recovery);
  const double braked = (v_fast * v_fast - vmax * vmax) / (2 * amax);
  const double expected = recovery + (length - braked - vmax * vmax / (2 * amax)) / vmax + vmax / amax;
  EXPECT_NEAR(q.duration(), expected, 2e-3 * expected);
  double previous = v_fast;
  for (std::size_t i = 0; i < q.t.size(); ++i)
  {
    const double speed = std::sqrt(q.x[i]) * path_rate;
    if (q.t[i] <= q.recovery_end)
      EXPECT_LE(speed, previous * (1.0 + 1e-12)) << q.t[i];
    else
      EXPECT_LE(speed, vmax * (1.0 + 1e-9)) << q.t[i];
    previous = speed;
  }
  for (double u : q.u)
    EXPECT_LE(std::abs(u) * path_rate, amax * (1.0 + 1e-9));
  // Too fast to stop before the end: refused naming the start state.
  options.start_speed = 20.0 / path_rate;
  try
  {
    timing::timeOptimalProfile(timing::CurvePath<DoubleGeodesicSe3>(line), bounds, options);
    ADD_FAILURE() << "a start that cannot stop within the path was accepted";
  }
  catch (const InvalidInputError& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("start_state:", 0), 0u) << e.what();
  }
}

TEST(StartJoin, BadInputNamesTheField)
{
  auto message = [](const TrajectoryRequest& r) -> std::string {
    try
    {
      generate(r, test::unhurriedLimits());
    }
    catch (const InvalidInputError& e)
    {
      return e.what();
    }
    return "";
  };
  TrajectoryRequest r = requestFrom(movingState(), "interpolating", "screw");
  r.times = { 0.0, 1.0, 2.0 };
  EXPECT_EQ(message(r).rfind("times[0]", 0), 0u) << message(r);
  r.times = { -1.0, 1.0, 2.0 };
  EXPECT_EQ(message(r).rfind("times[0]", 0), 0u) << message(r);
  r = requestFrom(movingState(), "bspline", "screw");
  r.knots = { 0, 0, 0, 0, 1, 1, 1, 1 };
  EXPECT_NE(message(r).find("knots"), std::string::npos) << message(r);
  r = requestFrom(movingState(), "interpolating", "screw");
  r.start_state->velocity.linear.x() = std::nan("");
  EXPECT_EQ(message(r).rfind("start_state.velocity.linear.x", 0), 0u) << message(r);
  r = requestFrom(movingState(), "interpolating", "screw");
  r.start_state->pose.q.coeffs() *= 2.0;
  EXPECT_EQ(message(r).rfind("start_state.pose.orientation", 0), 0u) << message(r);
  r = requestFrom(StartState(), "interpolating", "screw");
  r.waypoints.resize(1);
  r.start_state->pose = r.waypoints[0];
  EXPECT_EQ(message(r).rfind("waypoints", 0), 0u) << message(r);
  r = requestFrom(movingState(), "interpolating", "screw");
  r.waypoints.clear();
  EXPECT_EQ(message(r).rfind("waypoints", 0), 0u) << message(r);
}

}  // namespace
// Regression: the most common replanning call, one waypoint from a moving start under
// time_optimal, crashed with SIGSEGV (a timing profile of one grid point: the path after the
// joining segment had zero length) for every curve and both geometries. Now each is a motion from
// the start state, through the waypoint at rest, within its bounds.
TEST(StartJoin, OneWaypointFromAMovingStartUnderTimeOptimal)
{
  for (const char* curve : { "piecewise_geodesic", "bezier", "bspline", "interpolating", "hermite", "blended" })
    for (const char* geometry : { "double_geodesic", "screw" })
    {
      SCOPED_TRACE(std::string(curve) + " " + geometry);
      TrajectoryRequest r;
      r.waypoints = { pose({ 0.3, 0.0, 0.6 }, 0.0, { 0, 0, 1 }) };
      r.curve = curve;
      r.geometry = geometry;
      r.timing = "time_optimal";
      r.max_linear_velocity = 0.25;
      r.max_linear_acceleration = 0.5;
      r.sample_count = 2001;
      StartState s;
      s.pose = pose({ 0.6, 0.0, 0.3 }, 0.0, { 0, 0, 1 });
      s.velocity = twist({ 0.0, 0.3, 0.0 }, { 0.0, 0.0, 0.0 });
      r.start_state = s;
      const TrajectoryResult out = generate(r, test::unhurriedLimits());
      EXPECT_LT((out.samples.front().pose.p - s.pose.p).norm(), kSwitchTolerance);
      EXPECT_LT((out.samples.front().velocity.linear - s.velocity.linear).norm(), kSwitchTolerance);
      EXPECT_LT(test::poseDistance(out.samples.back().pose, r.waypoints[0]), 1e-9);
      EXPECT_LT(out.samples.back().velocity.linear.norm(), 1e-9);
      // The start (0.3 m/s) exceeds max_linear_velocity: it recovers by braking, then holds it.
      EXPECT_GT(out.recovery_time, 0.0);
      for (const TrajectorySample& x : out.samples)
      {
        if (x.time > out.recovery_time)
        {
          EXPECT_LE(x.velocity.linear.norm(), 0.25 * (1.0 + 1e-6)) << x.time;
        }
        EXPECT_LE(x.acceleration.linear.norm(), 0.5 * (1.0 + 1e-6)) << x.time;
      }
    }
}

/// Replanning as the action test's client does it: a jerk-limited time-optimal motion, then from
/// the state of every 30 ms of it a new motion to another pose. Every replan is served (where the
/// joined motion's timing does not converge, braking to rest and going from there does), starts in
/// that state and keeps the bounds on its samples.
TEST(StartJoin, ReplansFromEveryThirtyMillisecondsOfAJerkLimitedMotion)
{
  auto request = [](const std::vector<Pose<double>>& waypoints) {
    TrajectoryRequest r;
    r.waypoints = waypoints;
    r.curve = "piecewise_geodesic";
    r.timing = "time_optimal";
    r.max_linear_velocity = 1.0;
    r.max_angular_velocity = 2.0;
    r.max_linear_acceleration = 2.0;
    r.max_angular_acceleration = 4.0;
    r.max_linear_jerk = 20.0;
    r.max_angular_jerk = 40.0;
    return r;
  };
  TrajectoryRequest first = request({ pose({ 0.0, 0.0, 0.3 }, 0.0, { 0, 0, 1 }), pose({ 1.2, -0.4, 0.6 }, -0.5, { 0, 0, 1 }) });
  first.sample_period = 0.01;
  const TrajectoryResult played = generate(first, test::unhurriedLimits());
  ASSERT_GT(played.samples.size(), 150u);
  std::size_t tried = 0, refused = 0;
  for (std::size_t i = 10; i + 10 < played.samples.size(); i += 3)
  {
    const TrajectorySample& x = played.samples[i];
    SCOPED_TRACE("replan at t = " + std::to_string(x.time));
    TrajectoryRequest r = request({ pose({ 0.2, 0.8, 0.5 }, 1.0, { 0, 0, 1 }) });
    r.sample_count = 400;
    StartState s;
    s.pose = x.pose;
    s.velocity = x.velocity;
    s.acceleration = x.acceleration;
    r.start_state = s;
    ++tried;
    try
    {
      const TrajectoryResult out = generate(r, test::unhurriedLimits());
      // (Central differences over 1 ms of a jerk that jumps by up to 40 m/s³: 40 · 1e-3 / 2.)
      expectStartsIn(out, s, 0.02);
      for (const TrajectorySample& y : out.samples)
      {
        EXPECT_LE(y.velocity.linear.norm(), 1.0 * (1.0 + 1e-6)) << y.time;
        EXPECT_LE(y.velocity.angular.norm(), 2.0 * (1.0 + 1e-6)) << y.time;
        EXPECT_LE(y.acceleration.linear.norm(), 2.0 * (1.0 + 1e-6)) << y.time;
        EXPECT_LE(y.acceleration.angular.norm(), 4.0 * (1.0 + 1e-6)) << y.time;
      }
      EXPECT_LT(test::poseDistance(out.samples.back().pose, r.waypoints[0]), 1e-6);
    }
    catch (const LimitExceededError& e)
    {
      ADD_FAILURE() << e.what();
    }
    catch (const InterpolationError& e)
    {
      ++refused;
      const std::string m = e.what();
      EXPECT_TRUE(m.rfind("timing:", 0) == 0 || m.rfind("start_state:", 0) == 0) << m;
    }
  }
  EXPECT_GE(tried, 50u);
  EXPECT_EQ(refused, 0u);
}

// The joined curve evaluates the rest at t − offset, which rounds: at the joined curve's own
// breakpoints (the images of the rest's), the one-sided jets must be the rest's one-sided jets,
// not the neighbouring piece's (a corner of a piecewise geodesic, where a time-optimal motion
// stops, took the next piece's velocity with the braking of the previous one).
TEST(StartJoin, JoinedCurveTakesTheRequestedSideAtTheRestsBreakpoints)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> step(0.01, 3.0), start(-50.0, 50.0);
  const std::vector<Eigen::VectorXd> points{ Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(1.0, 0.0),
                                             Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(3.0, 1.0),
                                             Eigen::Vector2d(3.0, -2.0) };
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial)
  {
    std::vector<double> times{ start(rng) };
    for (std::size_t i = 1; i < points.size(); ++i)
      times.push_back(times.back() + step(rng));
    const auto rest = std::make_shared<const PiecewiseGeodesic<Euclidean>>(points, times);
    // The joining segment from (−1, 0) at rest, over [t0, t0 + h], onto the rest from times[0].
    const double t0 = start(rng), h = step(rng);
    VectorX<Jet<2>> start_jet(2);
    start_jet[0] = Jet<2>(-1.0);
    start_jet[1] = Jet<2>(0.0);
    const StartJoinedCurve<Euclidean> joined(Eigen::Vector2d(-1.0, 0.0), start_jet, t0, h, rest, times[0]);
    const std::vector<double> b = joined.breakpoints();
    ASSERT_EQ(b.size(), points.size() + 1);
    for (std::size_t i = 1; i + 1 < times.size(); ++i)
      for (Side side : { Side::kLeft, Side::kRight })
      {
        const std::size_t piece = side == Side::kLeft ? i - 1 : i;
        const Eigen::VectorXd v = (points[piece + 1] - points[piece]) / (times[piece + 1] - times[piece]);
        const VectorX<Jet<2>> j = joined.jet(Jet<2>::variable(b[i + 1]), side);
        for (int c = 0; c < 2; ++c)
          EXPECT_NEAR(j[c].coefficient(1), v[c], 1e-9 * (1.0 + v.norm())) << "trial " << trial << " breakpoint " << i;
        ++checked;
      }
  }
  EXPECT_EQ(checked, 200 * 3 * 2);
}

// A start three times faster than max_linear_velocity, whose curve the clock matching its speed
// would enter with nine times its acceleration: the recovery brakes within the acceleration
// bounds, so it lasts at least (|v0| − v_max) / a_max (the speed falls no faster than the
// acceleration bound), and every bound holds on 10⁵ samples. (It braked at 43 times the bound
// in 0.09 s.)
TEST(StartJoin, RecoveryFromAStartBeyondTheBoundsBrakesWithinThem)
{
  for (const char* geometry : { "double_geodesic", "screw" })
  {
    SCOPED_TRACE(geometry);
    TrajectoryRequest r;
    r.waypoints = { pose({ 1.1353, 1.4397, 1.8955 }, 2.6, { 0.1, 0.3, 0.95 }) };
    r.times = { 0.7 };
    r.curve = "interpolating";
    r.end_condition = "clamped";
    r.geometry = geometry;
    r.timing = "time_optimal";
    r.max_linear_velocity = 0.3;
    r.max_angular_velocity = 0.4;
    r.max_linear_acceleration = 0.5;
    r.max_angular_acceleration = 0.8;
    r.start_velocity = twist({ 0.1185, -0.039, 0.0156 }, { 0.205, 0.195, -0.15 });
    r.end_velocity = twist({ -0.046, -0.087, 0.0019 }, { -0.024, 0.1145, 0.1127 });
    r.sample_count = 100001;
    StartState s;
    s.pose = pose({ 1.3354, 1.2006, 2.1024 }, 2.75, { 0.2, 0.3, 0.93 });
    s.velocity = twist({ 0.9, 0.0, 0.0 }, { 0.0, 0.0, 0.1 });
    r.start_state = s;
    const TrajectoryResult out = generate(r, test::unhurriedLimits());
    EXPECT_LT((out.samples.front().velocity.linear - s.velocity.linear).norm(), kSwitchTolerance);
    EXPECT_GE(out.recovery_time, (0.9 - 0.3) / 0.5 * (1.0 - 1e-6));
    double previous = std::numeric_limits<double>::infinity();
    for (const TrajectorySample& x : out.samples)
    {
      const double speed = x.velocity.linear.norm();
      if (x.time <= out.recovery_time)
      {
        EXPECT_LE(speed, previous * (1.0 + 1e-9) + 1e-12) << x.time;  // the exceeded speed never rises
      }
      else
      {
        EXPECT_LE(speed, 0.3 * (1.0 + 1e-6)) << x.time;
      }
      previous = speed;
      EXPECT_LE(x.velocity.angular.norm(), 0.4 * (1.0 + 1e-6)) << x.time;
      EXPECT_LE(x.acceleration.linear.norm(), 0.5 * (1.0 + 1e-6)) << x.time;
      EXPECT_LE(x.acceleration.angular.norm(), 0.8 * (1.0 + 1e-6)) << x.time;
    }
    // Independently of the reported accelerations: the mean acceleration over each sample
    // interval, from the velocities, is within the bound (the acceleration jumps where the
    // profile switches, so no pointwise difference quotient is compared there), and the
    // velocities agree with central differences of the positions.
    for (std::size_t i = 1; i + 1 < out.samples.size(); ++i)
    {
      const TrajectorySample &a = out.samples[i - 1], &b = out.samples[i], &c = out.samples[i + 1];
      EXPECT_LE((c.velocity.linear - b.velocity.linear).norm() / (c.time - b.time), 0.5 * (1.0 + 1e-3)) << b.time;
      const Eigen::Vector3d fd = (c.pose.p - a.pose.p) / (c.time - a.time);
      // (Across a jump Δa ≤ 2 a_max of the acceleration the central difference is off by at most
      // Δa · (c.time − a.time) / 8.)
      EXPECT_LT((fd - b.velocity.linear).norm(), 0.25 * 0.5 * (c.time - a.time) + 1e-9) << b.time;
    }
  }
}

// end_condition 'start' continues the start state itself: from three times the velocity bound,
// this spline bends so sharply that braking along it would take 34 times the acceleration bound
// (it was served so, then refused naming end_condition). A start beyond a velocity bound now brakes
// to rest along its own directions first (curves/braked_start.h): the fastest recovery the
// acceleration bounds allow, (0.9 − 0.3) / 0.5 = 1.2 s, a stop after 0.9 / 0.5 = 1.8 s, then the
// spline from rest at the stopping pose; with 'start' and with 'clamped' alike, within the bounds.
TEST(StartJoin, StartBeyondAVelocityBoundBrakesToRestFirst)
{
  TrajectoryRequest r;
  r.waypoints = { Pose<double>(Eigen::Quaterniond(0.82582406459599578, 0.17251512573128769, -0.50342962866468843,
                                                  0.18657908433316051),
                               Eigen::Vector3d(1.0321243413931693, -0.16462585364415006, 1.3440602088887645)),
                  Pose<double>(Eigen::Quaterniond(-0.21926715463381077, -0.35799638087216579, -0.15171323389255953,
                                                  0.89484277995806916),
                               Eigen::Vector3d(1.1013362493491887, 0.19760539971676644, 0.29629445328473936)) };
  r.curve = "interpolating";
  r.end_condition = "start";
  r.geometry = "screw";
  r.timing = "time_optimal";
  r.max_linear_velocity = 0.3;
  r.max_angular_velocity = 0.4;
  r.max_linear_acceleration = 0.5;
  r.max_angular_acceleration = 0.8;
  r.sample_count = 20001;
  StartState s;
  s.pose = Pose<double>(Eigen::Quaterniond(0.7308271314684075, 0.19722074629737862, -0.60387851538240622,
                                           0.24965259822221963),
                        Eigen::Vector3d(0.73199262184071534, -0.078073822530450754, 1.1380755084166654));
  s.velocity = twist({ 0.9, 0.0, 0.0 }, { 0.0, 0.0, 0.1 });
  r.start_state = s;
  for (const char* end_condition : { "start", "clamped" })
  {
    SCOPED_TRACE(end_condition);
    r.end_condition = end_condition;
    const TrajectoryResult out = generate(r, test::unhurriedLimits());
    EXPECT_NEAR(out.recovery_time, 1.2, 1e-12);
    EXPECT_NEAR(out.stop_time, 1.8, 1e-12);
    const TrajectorySample& first = out.samples.front();
    EXPECT_LT(test::poseDistance(first.pose, s.pose), 1e-12);
    EXPECT_LT((first.velocity.linear - s.velocity.linear).norm(), kSwitchTolerance);
    EXPECT_LT((first.velocity.angular - s.velocity.angular).norm(), kSwitchTolerance);
    EXPECT_LT(first.acceleration.linear.norm() + first.acceleration.angular.norm(), kSwitchTolerance);
    EXPECT_LT(test::poseDistance(out.samples.back().pose, r.waypoints.back()), 1e-9);
    double previous = std::numeric_limits<double>::infinity();
    for (const TrajectorySample& x : out.samples)
    {
      const double speed = x.velocity.linear.norm();
      if (x.time <= out.recovery_time)
      {
        // The exceeded speed falls at the acceleration bound, along the start's direction.
        EXPECT_NEAR(speed, 0.9 - 0.5 * x.time, 1e-12) << x.time;
        EXPECT_LE(speed, previous) << x.time;
      }
      else
      {
        EXPECT_LE(speed, 0.3 * (1.0 + 1e-6)) << x.time;
      }
      previous = speed;
      EXPECT_LE(x.velocity.angular.norm(), 0.4 * (1.0 + 1e-6)) << x.time;
      if (x.time > 0.0)
      {
        EXPECT_LE(x.acceleration.linear.norm(), 0.5 * (1.0 + 1e-6)) << x.time;
        EXPECT_LE(x.acceleration.angular.norm(), 0.8 * (1.0 + 1e-6)) << x.time;
      }
    }
    // The figures include the braking: the start's speed, the decelerations at the bounds.
    EXPECT_EQ(out.figures.max_linear_speed, 0.9);
    EXPECT_NEAR(out.figures.max_linear_acceleration, 0.5, 1e-6 * 0.5);
  }
}

// A moving start within the bounds whose spline (end_condition 'start' continues the start state
// itself) bends too sharply for its speed: the time-optimal timing along it did not converge
// within max_linear_acceleration and the request was refused ("... after 16 corrections"; the
// request-space grid's interpolating/start double_geodesic time_optimal/al N=1 times=even
// start=moving). It brakes to rest along its own directions first (stop_time, no recovery: the
// start is within the bounds), then moves from rest to the waypoint: served within the bound.
TEST(StartJoin, MovingStartThatCannotContinueWithinTheBoundsBrakesToRest)
{
  TrajectoryRequest r;
  r.waypoints = { Pose<double>(Eigen::Quaterniond(0.23750523422383812, 0.036020526275221898, 0.26797785078609077,
                                                  0.93299606477798369),
                               Eigen::Vector3d(1.1353100277014709, 1.4397380422075639, 1.8955473932535476)) };
  r.times = { 0.7 };
  r.curve = "interpolating";
  r.end_condition = "start";
  r.geometry = "double_geodesic";
  r.timing = "time_optimal";
  r.max_linear_acceleration = 0.5;
  r.sample_count = 20001;
  StartState s;
  s.pose = Pose<double>(Eigen::Quaterniond(0.19656327655251482, 0.18360423429639572, 0.27900563721701122,
                                           0.92185043139356582),
                        Eigen::Vector3d(1.3353614309682669, 1.20057334019981, 2.1023798891639536));
  s.velocity = twist({ 0.12, -0.05, 0.04 }, { 0.05, 0.1, -0.08 });
  s.acceleration = twist({ -0.1, 0.05, 0.1 }, { 0.1, -0.1, 0.05 });
  r.start_state = s;
  const TrajectoryResult out = generate(r, test::unhurriedLimits());
  // Only the linear channel has an acceleration bound: it stops in |v| / 0.5 s, the rotation with it.
  EXPECT_NEAR(out.stop_time, s.velocity.linear.norm() / 0.5, 1e-12);
  EXPECT_EQ(out.recovery_time, 0.0);
  const TrajectorySample& first = out.samples.front();
  EXPECT_LT(test::poseDistance(first.pose, s.pose), 1e-12);
  EXPECT_LT((first.velocity.linear - s.velocity.linear).norm(), kSwitchTolerance);
  EXPECT_LT((first.velocity.angular - s.velocity.angular).norm(), kSwitchTolerance);
  EXPECT_LT((first.acceleration.linear - s.acceleration.linear).norm(), kSwitchTolerance);
  EXPECT_LT((first.acceleration.angular - s.acceleration.angular).norm(), kSwitchTolerance);
  EXPECT_LT(test::poseDistance(out.samples.back().pose, r.waypoints[0]), 1e-9);
  EXPECT_LT(out.samples.back().velocity.linear.norm() + out.samples.back().velocity.angular.norm(), 1e-9);
  for (std::size_t i = 1; i < out.samples.size(); ++i)
  {
    const TrajectorySample& x = out.samples[i];
    EXPECT_LE(x.acceleration.linear.norm(), 0.5 * (1.0 + 1e-6)) << x.time;
    // Independently of the reported accelerations: the mean over each sample interval.
    const TrajectorySample& w = out.samples[i - 1];
    EXPECT_LE((x.velocity.linear - w.velocity.linear).norm() / (x.time - w.time), 0.5 * (1.0 + 1e-6)) << x.time;
    if (x.time <= out.stop_time)
    {
      // Braking along the start's own direction.
      EXPECT_NEAR(x.velocity.linear.norm(), s.velocity.linear.norm() - 0.5 * x.time, 1e-12) << x.time;
    }
  }
}

}  // namespace se3_interpolation
