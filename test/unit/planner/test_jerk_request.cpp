// The jerk bounds through the request (max_linear_jerk, max_angular_jerk): time_optimal with
// jerk bounds against the textbook double S on a line, every bound and the continuity of the
// acceleration by differences of the reported accelerations on curved paths of both geometries, a
// moving start kept, `stretch` covering the jerk (k³) and refusing a curve whose acceleration
// jumps, the figures equal to the measured peaks, and bad values refused naming the field.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "se3_interpolation/planner/planner.h"
#include "spline_test_utils.h"
#include "test_utils.h"

using namespace se3_interpolation;
using namespace se3_interpolation::test;

namespace
{
/// The duration of the rest-to-rest double S of length L under v, a, j (L. Biagiotti,
/// C. Melchiorri, "Trajectory Planning for Automatic Machines and Robots", §3.4, with
/// v0 = v1 = 0), written here from its cases independently of the code under test.
double doubleSDuration(double L, double v, double a, double j)
{
  // Velocity limit reached?
  double tj = v * j >= a * a ? a / j : std::sqrt(v / j);
  double ta = v * j >= a * a ? tj + v / a : 2.0 * tj;
  if (L / v - ta >= 0.0)
    return ta + L / v;  // T = 2 Ta + Tv with Tv = L/v − Ta
  // Not reached: with the acceleration limit reached, L = a (Ta − Tj) Ta.
  tj = a / j;
  ta = 0.5 * (tj + std::sqrt(tj * tj + 4.0 * L / a));
  if (ta >= 2.0 * tj)
    return 2.0 * ta;
  // Neither: L = 2 j Tj³.
  return 4.0 * std::cbrt(L / (2.0 * j));
}

TrajectoryRequest line(double length, const Eigen::Vector3d& axis, double angle)
{
  TrajectoryRequest r;
  Pose<double> a, b;
  b.p = length * axis;
  b.q = Quaternion<double>(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
  r.waypoints = { a, b };
  r.curve = "piecewise_geodesic";
  r.timing = "time_optimal";
  return r;
}

/// time_optimal under all six bounds (0.5 m/s, 1 rad/s, 1 m/s², 2 rad/s², 5 m/s³, 10 rad/s³),
/// sampled at 1 kHz.
void withAllBounds(TrajectoryRequest* r)
{
  r->timing = "time_optimal";
  r->max_linear_velocity = 0.5;
  r->max_angular_velocity = 1.0;
  r->max_linear_acceleration = 1.0;
  r->max_angular_acceleration = 2.0;
  r->max_linear_jerk = 5.0;
  r->max_angular_jerk = 10.0;
  r->sample_period = 1e-3;
}

struct Measured
{
  double v[2]{}, a[2]{}, j[2]{};
  double acceleration_step = 0.0;  ///< largest |Δa| between neighbouring samples, both channels
};

/// Peaks from the samples: the reported velocities and accelerations, and the jerk as the
/// differences of the reported accelerations (independent of the code's jerk).
Measured measure(const TrajectoryResult& out)
{
  Measured m;
  for (std::size_t i = 0; i < out.samples.size(); ++i)
  {
    const auto& s = out.samples[i];
    m.v[0] = std::max(m.v[0], s.velocity.linear.norm());
    m.v[1] = std::max(m.v[1], s.velocity.angular.norm());
    m.a[0] = std::max(m.a[0], s.acceleration.linear.norm());
    m.a[1] = std::max(m.a[1], s.acceleration.angular.norm());
    if (i == 0)
      continue;
    const auto& p = out.samples[i - 1];
    const double dt = s.time - p.time;
    const double dl = (s.acceleration.linear - p.acceleration.linear).norm();
    const double da = (s.acceleration.angular - p.acceleration.angular).norm();
    m.j[0] = std::max(m.j[0], dl / dt);
    m.j[1] = std::max(m.j[1], da / dt);
    m.acceleration_step = std::max({ m.acceleration_step, dl, da });
  }
  return m;
}

void expectWithinBounds(const TrajectoryRequest& r, const TrajectoryResult& out, const std::string& what)
{
  const Measured m = measure(out);
  const double tol = 1.0 + 1e-6;
  // The differences of accelerations are mean jerks over each step: never above the peak.
  const struct
  {
    const char* name;
    double bound;
    double peak;
  } checks[] = { { "max_linear_velocity", r.max_linear_velocity, m.v[0] },
                 { "max_angular_velocity", r.max_angular_velocity, m.v[1] },
                 { "max_linear_acceleration", r.max_linear_acceleration, m.a[0] },
                 { "max_angular_acceleration", r.max_angular_acceleration, m.a[1] },
                 { "max_linear_jerk", r.max_linear_jerk, m.j[0] },
                 { "max_angular_jerk", r.max_angular_jerk, m.j[1] } };
  for (const auto& check : checks)
    if (check.bound > 0.0)
    {
      EXPECT_LE(check.peak, check.bound * tol) << what << ": " << check.name;
    }
  // The figures are the motion's peaks: never below what the samples show, and within 1 % of it
  // on a dense sampling (the jerk differences average over a step).
  EXPECT_GE(out.figures.max_linear_speed * tol, m.v[0]) << what;
  EXPECT_GE(out.figures.max_linear_acceleration * tol, m.a[0]) << what;
  EXPECT_GE(out.figures.max_angular_acceleration * tol, m.a[1]) << what;
  EXPECT_GE(out.figures.max_linear_jerk * tol, m.j[0]) << what;
  EXPECT_GE(out.figures.max_angular_jerk * tol, m.j[1]) << what;
  EXPECT_LE(out.figures.max_linear_acceleration, m.a[0] * 1.01 + 1e-12) << what;
  EXPECT_LE(out.figures.max_linear_jerk, m.j[0] * 1.01 + 1e-12) << what;
  // Rest to rest: zero velocity and acceleration at both ends.
  for (const auto* s : { &out.samples.front(), &out.samples.back() })
  {
    EXPECT_LT(s->velocity.linear.norm() + s->velocity.angular.norm(), 1e-9) << what;
    EXPECT_LT(s->acceleration.linear.norm() + s->acceleration.angular.norm(), 1e-6) << what;
  }
}
}  // namespace

TEST(JerkRequest, StraightLinesTakeTheDoubleSDuration)
{
  struct Case
  {
    double length, v, a, j;
  };
  // Every case of the double S: both limits reached; v not reached; a not reached; neither.
  const Case cases[] = { { 2.0, 0.5, 1.0, 5.0 }, { 0.3, 1.0, 1.0, 20.0 }, { 2.0, 0.2, 2.0, 5.0 },
                         { 0.01, 1.0, 2.0, 10.0 }, { 1.0, 2.0, 13.0, 6500.0 } };
  for (const Case& c : cases)
    for (const char* geometry : { "double_geodesic", "screw" })
    {
      TrajectoryRequest r = line(c.length, Eigen::Vector3d(1.0, 2.0, -2.0).normalized(), 0.0);
      r.geometry = geometry;
      r.max_linear_velocity = c.v;
      r.max_linear_acceleration = c.a;
      r.max_linear_jerk = c.j;
      r.sample_count = 20001;
      const TrajectoryResult out = generate(r, unhurriedLimits());
      const double expected = doubleSDuration(c.length, c.v, c.a, c.j);
      const std::string what = std::string(geometry) + " L " + std::to_string(c.length) + " v " +
                               std::to_string(c.v) + " a " + std::to_string(c.a) + " j " + std::to_string(c.j);
      EXPECT_NEAR(out.duration, expected, 0.01 * expected) << what;
      EXPECT_GE(out.duration, expected * (1.0 - 1e-9)) << what;  // never faster than the optimum
      expectWithinBounds(r, out, what);
    }
  // Rotation about a fixed axis: the angular channel alone.
  TrajectoryRequest r = line(0.0, Eigen::Vector3d::UnitX(), 2.0);
  r.max_angular_velocity = 1.0;
  r.max_angular_acceleration = 2.0;
  r.max_angular_jerk = 10.0;
  r.sample_count = 20001;
  const TrajectoryResult out = generate(r, unhurriedLimits());
  const double expected = doubleSDuration(2.0, 1.0, 2.0, 10.0);
  EXPECT_NEAR(out.duration, expected, 0.01 * expected);
  expectWithinBounds(r, out, "rotation");
}

TEST(JerkRequest, CurvedPathsKeepEveryBoundWithContinuousAcceleration)
{
  std::mt19937 rng(2801);
  for (const char* geometry : { "double_geodesic", "screw" })
    for (const char* curve : { "interpolating", "bspline", "blended", "hermite", "piecewise_geodesic" })
    {
      TrajectoryRequest r;
      r.waypoints = randomPolygon(rng, 5);
      r.curve = curve;
      r.geometry = geometry;
      withAllBounds(&r);
      const TrajectoryResult out = generate(r, unhurriedLimits());
      const std::string what = std::string(geometry) + " " + curve;
      expectWithinBounds(r, out, what);
      // Continuous acceleration: no step larger than the jerk bound allows over one sample.
      EXPECT_LE(measure(out).acceleration_step, 10.0 * 1e-3 * (1.0 + 1e-6)) << what;
      // The waypoints' times are where the motion passes them (interpolating, hermite).
      if (std::string(curve) == "interpolating" || std::string(curve) == "hermite")
      {
        TrajectoryRequest at = r;
        at.sample_period = 0.0;
        at.sample_times = out.waypoint_times;
        const TrajectoryResult again = generate(at, unhurriedLimits());
        for (std::size_t i = 0; i < r.waypoints.size(); ++i)
          EXPECT_LT(poseDistance(again.samples[i].pose, r.waypoints[i]), 1e-6) << what << " waypoint " << i;
      }
    }
}

TEST(JerkRequest, ALooseJerkBoundCostsLittleOverTheAccelerationOnlyOptimum)
{
  std::mt19937 rng(2802);
  TrajectoryRequest r;
  r.waypoints = randomPolygon(rng, 6);
  withAllBounds(&r);
  r.max_linear_jerk = r.max_angular_jerk = 0.0;  // first the acceleration-only optimum
  r.sample_period = 0.0;
  r.sample_count = 2;
  const double optimum = generate(r, unhurriedLimits()).duration;
  // a/j ≤ 1 ms for both channels.
  r.max_linear_jerk = 1000.0;
  r.max_angular_jerk = 2000.0;
  const double jerk_limited = generate(r, unhurriedLimits()).duration;
  EXPECT_GE(jerk_limited, optimum * (1.0 - 1e-9));
  EXPECT_LE(jerk_limited, optimum * 1.03);
}

TEST(JerkRequest, AMovingStartIsKept)
{
  std::mt19937 rng(2803);
  StartState s;
  s.pose = randomPose(rng);
  s.velocity.linear = Eigen::Vector3d(0.1, -0.05, 0.02);
  s.velocity.angular = Eigen::Vector3d(0.0, 0.1, 0.0);
  TrajectoryRequest r;
  r.waypoints = randomPolygon(rng, 3);
  r.start_state = s;
  r.curve = "interpolating";
  withAllBounds(&r);
  const TrajectoryResult out = generate(r, unhurriedLimits());
  const TrajectorySample& first = out.samples.front();
  EXPECT_LT(poseDistance(first.pose, s.pose), 1e-9);
  EXPECT_LT((first.velocity.linear - s.velocity.linear).norm(), 1e-9);
  EXPECT_LT((first.velocity.angular - s.velocity.angular).norm(), 1e-9);
  EXPECT_LT(first.acceleration.linear.norm() + first.acceleration.angular.norm(), 1e-9);
  const Measured m = measure(out);
  EXPECT_LE(m.j[0], r.max_linear_jerk * (1.0 + 1e-6));
  EXPECT_LE(m.j[1], r.max_angular_jerk * (1.0 + 1e-6));
  EXPECT_LE(m.a[0], r.max_linear_acceleration * (1.0 + 1e-6));
}

TEST(JerkRequest, StretchCoversTheJerkBound)
{
  std::mt19937 rng(2804);
  TrajectoryRequest r;
  r.waypoints = randomPolygon(rng, 5);
  r.curve = "interpolating";
  r.max_linear_jerk = 0.5;
  r.max_angular_jerk = 0.5;
  r.sample_period = 1e-3;
  const TrajectoryResult out = generate(r, unhurriedLimits());
  EXPECT_GT(out.time_scale, 1.0);
  const Measured m = measure(out);
  EXPECT_LE(m.j[0], r.max_linear_jerk * (1.0 + 1e-6));
  EXPECT_LE(m.j[1], r.max_angular_jerk * (1.0 + 1e-6));
  // The binding bound is met: the stretch is the smallest that fits (k³ scaling).
  const double binding = std::max(out.figures.max_linear_jerk / r.max_linear_jerk,
                                  out.figures.max_angular_jerk / r.max_angular_jerk);
  EXPECT_NEAR(binding, 1.0, 1e-6);
  EXPECT_GE(std::max(m.j[0] / r.max_linear_jerk, m.j[1] / r.max_angular_jerk), 0.99);
  // Without the stretch, the same curve's jerk is k³ times as large.
  TrajectoryRequest unbounded = r;
  unbounded.max_linear_jerk = 0.0;
  unbounded.max_angular_jerk = 0.0;
  const Measured u = measure(generate(unbounded, unhurriedLimits()));
  const double k3 = out.time_scale * out.time_scale * out.time_scale;
  EXPECT_NEAR(std::max(u.j[0] / r.max_linear_jerk, u.j[1] / r.max_angular_jerk), k3, 0.02 * k3);
}

TEST(JerkRequest, StretchRefusesACurveWhoseAccelerationJumps)
{
  std::mt19937 rng(2805);
  for (const char* curve : { "piecewise_geodesic", "hermite" })
  {
    TrajectoryRequest r;
    r.waypoints = randomPolygon(rng, 4);
    r.curve = curve;
    r.max_linear_jerk = 1.0;
    try
    {
      generate(r, unhurriedLimits());
      ADD_FAILURE() << curve << " was stretched";
    }
    catch (const InvalidInputError& e)
    {
      EXPECT_EQ(std::string(e.what()).rfind("max_linear_jerk: ", 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find("time_optimal"), std::string::npos) << e.what();
    }
  }
}

TEST(JerkRequest, BadValuesAreRefusedNamingTheField)
{
  for (const char* field : { "max_linear_jerk", "max_angular_jerk" })
    for (double bad : { -1.0, std::nan(""), std::numeric_limits<double>::infinity() })
    {
      TrajectoryRequest r = line(1.0, Eigen::Vector3d::UnitX(), 0.0);
      (std::string(field) == "max_linear_jerk" ? r.max_linear_jerk : r.max_angular_jerk) = bad;
      try
      {
        generate(r, unhurriedLimits());
        ADD_FAILURE() << field << " " << bad << " accepted";
      }
      catch (const InvalidInputError& e)
      {
        EXPECT_EQ(std::string(e.what()).rfind(std::string(field) + ": ", 0), 0u) << e.what();
      }
    }
  // On the sphere only the angular channel exists.
  SphereRequest s;
  s.waypoints = { Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY() };
  s.max_linear_jerk = 1.0;
  try
  {
    generate(s, unhurriedLimits());
    ADD_FAILURE() << "max_linear_jerk accepted on the sphere";
  }
  catch (const InvalidInputError& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("max_linear_jerk: ", 0), 0u) << e.what();
  }
}

TEST(JerkRequest, TheSphereTakesTheAngularJerkBound)
{
  SphereRequest s;
  s.waypoints = { Eigen::Vector3d::UnitX(), Eigen::Vector3d(1.0, 1.0, 0.0).normalized(),
                  Eigen::Vector3d(0.0, 1.0, 1.0).normalized() };
  s.timing = "time_optimal";
  s.max_angular_velocity = 1.0;
  s.max_angular_acceleration = 2.0;
  s.max_angular_jerk = 8.0;
  s.sample_period = 1e-3;
  const SphereResult out = generate(s, unhurriedLimits());
  double jerk = 0.0;
  for (std::size_t i = 1; i < out.samples.size(); ++i)
    jerk = std::max(jerk, (out.samples[i].acceleration - out.samples[i - 1].acceleration).norm() /
                              (out.samples[i].time - out.samples[i - 1].time));
  // Covariant accelerations at neighbouring points differ by their tangent spaces' turn too
  // (of order |a| |v| dt): the bound within 1 %.
  EXPECT_LE(jerk, s.max_angular_jerk * 1.01);
  EXPECT_GT(out.figures.max_angular_jerk, 0.0);
  EXPECT_LE(out.figures.max_angular_jerk, s.max_angular_jerk * (1.0 + 1e-6));
}
