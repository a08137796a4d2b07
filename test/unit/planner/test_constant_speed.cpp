// timing `constant_speed` through the request: the closed-form ramps and window on straight lines
// (translation, rotation about a fixed axis), the chord speed √(|ṗ|² + ρ²|ω|²) measured by central
// differences of the sampled poses on a circle-like blended polygon of both geometries, every bound
// by the reported velocities and accelerations and the jerk by their differences, the waypoint
// times, and every refusal naming its field.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "se3_interpolation/planner/planner.h"
#include "test_utils.h"

using namespace se3_interpolation;
using namespace se3_interpolation::test;

namespace
{
/// The quintic smoothstep's integral, written from its definition: ∫₀^τ (10x³ − 15x⁴ + 6x⁵) dx.
double smoothstepIntegral(double tau)
{
  return 2.5 * std::pow(tau, 4) - 3.0 * std::pow(tau, 5) + std::pow(tau, 6);
}

TrajectoryRequest line(double length, double angle)
{
  TrajectoryRequest r;
  Pose<double> a, b;
  b.p = length * Eigen::Vector3d(2.0, -1.0, 2.0).normalized();
  b.q = Quaternion<double>(Eigen::AngleAxisd(angle, Eigen::Vector3d(0.0, 0.6, 0.8)));
  r.waypoints = { a, b };
  r.curve = "piecewise_geodesic";
  r.timing = "constant_speed";
  return r;
}

/// A regular polygon of `n` corners on a circle of radius 1 (closed back to its first corner's
/// neighbour), the body turning about z by `turn` per corner, blended with radius `blend`.
TrajectoryRequest polygon(int n, double turn, double blend)
{
  TrajectoryRequest r;
  for (int i = 0; i <= n; ++i)
  {
    const double phi = 2.0 * M_PI * i / n;
    Pose<double> p;
    p.p = Eigen::Vector3d(std::cos(phi), std::sin(phi), 0.1 * i);
    p.q = Quaternion<double>(Eigen::AngleAxisd(turn * i, Eigen::Vector3d::UnitZ()));
    r.waypoints.push_back(p);
  }
  r.curve = "piecewise_geodesic";
  r.blend_radius = blend;
  r.timing = "constant_speed";
  return r;
}

/// The chord speed at t by central differences of the sampled poses at t ± h.
double chordSpeedByDifferences(const TrajectorySample& before, const TrajectorySample& after, double rho)
{
  const double dt = after.time - before.time;
  const double dp = (after.pose.p - before.pose.p).norm() / dt;
  const double dtheta = rotationAngle(Quaternion<double>(before.pose.q.conjugate() * after.pose.q)) / dt;
  return std::sqrt(dp * dp + rho * rho * dtheta * dtheta);
}

/// Every bound by the samples: velocities and accelerations as reported, jerk by the differences of
/// the accelerations; the figures at least the samples' peaks; rest at both ends.
void expectWithinBounds(const TrajectoryRequest& r, const TrajectoryResult& out, const std::string& what)
{
  const double tol = 1.0 + 1e-6;
  double v[2]{}, a[2]{}, j[2]{};
  for (std::size_t i = 0; i < out.samples.size(); ++i)
  {
    const auto& s = out.samples[i];
    v[0] = std::max(v[0], s.velocity.linear.norm());
    v[1] = std::max(v[1], s.velocity.angular.norm());
    a[0] = std::max(a[0], s.acceleration.linear.norm());
    a[1] = std::max(a[1], s.acceleration.angular.norm());
    if (i == 0)
      continue;
    const auto& p = out.samples[i - 1];
    j[0] = std::max(j[0], (s.acceleration.linear - p.acceleration.linear).norm() / (s.time - p.time));
    j[1] = std::max(j[1], (s.acceleration.angular - p.acceleration.angular).norm() / (s.time - p.time));
  }
  const double bound_v[2] = { r.max_linear_velocity, r.max_angular_velocity };
  const double bound_a[2] = { r.max_linear_acceleration, r.max_angular_acceleration };
  const double bound_j[2] = { r.max_linear_jerk, r.max_angular_jerk };
  for (int c = 0; c < 2; ++c)
  {
    if (bound_v[c] > 0.0)
    {
      EXPECT_LE(v[c], bound_v[c] * tol) << what << " channel " << c;
    }
    if (bound_a[c] > 0.0)
    {
      EXPECT_LE(a[c], bound_a[c] * tol) << what << " channel " << c;
    }
    if (bound_j[c] > 0.0)
    {
      EXPECT_LE(j[c], bound_j[c] * tol) << what << " channel " << c;
    }
  }
  EXPECT_GE(out.figures.max_linear_speed * tol, v[0]) << what;
  EXPECT_GE(out.figures.max_angular_speed * tol, v[1]) << what;
  EXPECT_GE(out.figures.max_linear_acceleration * tol, a[0]) << what;
  EXPECT_GE(out.figures.max_angular_acceleration * tol, a[1]) << what;
  for (const auto* s : { &out.samples.front(), &out.samples.back() })
  {
    EXPECT_LT(s->velocity.linear.norm() + s->velocity.angular.norm(), 1e-9) << what;
    EXPECT_LT(s->acceleration.linear.norm() + s->acceleration.angular.norm(), 1e-9) << what;
  }
}

/// Expects `r` refused with a message that starts with `field` and contains `also`.
void expectRefused(const TrajectoryRequest& r, const std::string& field, const std::string& also = "")
{
  try
  {
    generate(r, unhurriedLimits());
    ADD_FAILURE() << "served; expected a refusal naming " << field;
  }
  catch (const InvalidInputError& e)
  {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(field + ":", 0), 0u) << m;
    EXPECT_NE(m.find(also), std::string::npos) << m;
  }
}
}  // namespace

TEST(ConstantSpeed, StraightLinesTakeTheClosedFormRampsAndWindow)
{
  struct Case
  {
    double length, angle, rho, speed, a, j;
  };
  // Translation; translation and rotation (the double geodesic's chord metric); rotation alone;
  // each with and without a jerk bound that lengthens the ramps.
  const Case cases[] = { { 2.0, 0.0, 1.0, 0.5, 1.0, 0.0 },  { 2.0, 0.0, 1.0, 0.5, 1.0, 1.0 },
                         { 1.5, 1.0, 0.4, 0.3, 2.0, 0.0 },  { 1.5, 1.0, 0.4, 0.3, 2.0, 3.0 },
                         { 0.0, 2.0, 0.5, 0.2, 0.5, 0.0 } };
  for (const Case& c : cases)
  {
    TrajectoryRequest r = line(c.length, c.angle);
    r.rotation_scale = c.rho;
    r.speed = c.speed;
    r.max_linear_acceleration = c.a;
    r.max_linear_jerk = c.j;
    r.sample_count = 4001;
    const std::string what = "L " + std::to_string(c.length) + " angle " + std::to_string(c.angle) + " j " +
                             std::to_string(c.j);
    const TrajectoryResult out = generate(r, unhurriedLimits());
    // The chord length and the ramp: 15/8 V/T = a, and with a jerk bound 10/√3 V/T² = j if longer
    // (the straight line's ramp is exactly the smoothstep's; on a line w = (1, ρ²) is the metric).
    const double total = std::hypot(c.length, c.rho * c.angle);
    double ramp = 15.0 / 8.0 * c.speed / c.a;
    if (c.j > 0.0)
      ramp = std::max(ramp, std::sqrt(10.0 / std::sqrt(3.0) * c.speed / c.j));
    EXPECT_NEAR(out.duration, total / c.speed + ramp, 1e-6 * out.duration) << what;
    EXPECT_NEAR(out.constant_speed_start, ramp, 1e-9) << what;
    EXPECT_NEAR(out.constant_speed_end, total / c.speed, 1e-6) << what;
    // Every sample's arc length is the closed form's: σ = V T P(t/T) in the ramps, linear between.
    for (const auto& s : out.samples)
    {
      const double t = s.time;
      const double end = out.duration;
      double arc;
      if (t <= ramp)
        arc = c.speed * ramp * smoothstepIntegral(t / ramp);
      else if (t >= end - ramp)
        arc = total - c.speed * ramp * smoothstepIntegral((end - t) / ramp);
      else
        arc = 0.5 * c.speed * ramp + c.speed * (t - ramp);
      const double travelled =
          std::hypot(s.pose.p.norm(), c.rho * rotationAngle(Quaternion<double>(r.waypoints[0].q.conjugate() * s.pose.q)));
      EXPECT_NEAR(travelled, arc, 1e-7 * total) << what << " t " << t;
    }
    // The peak acceleration is the bound itself when it sets the ramp.
    const double peak = std::hypot(out.figures.max_linear_acceleration, c.rho * out.figures.max_angular_acceleration);
    if (c.j == 0.0)
    {
      EXPECT_NEAR(peak, c.a, 1e-6 * c.a) << what;
    }
    expectWithinBounds(r, out, what);
  }
}

TEST(ConstantSpeed, TheChordSpeedIsHeldOnACircleLikeBlendedPolygon)
{
  for (const char* geometry : { "double_geodesic", "screw" })
  {
    TrajectoryRequest r = polygon(12, 0.3, 0.2);
    r.geometry = geometry;
    r.rotation_scale = 0.5;
    r.speed = 0.25;
    r.max_linear_velocity = 0.5;
    r.max_angular_velocity = 2.0;
    r.max_linear_acceleration = 1.0;
    r.max_angular_acceleration = 4.0;
    r.max_linear_jerk = 20.0;
    r.max_angular_jerk = 80.0;
    r.sample_period = 1e-3;
    const TrajectoryResult out = generate(r, unhurriedLimits());
    expectWithinBounds(r, out, geometry);
    ASSERT_GT(out.constant_speed_end, out.constant_speed_start + 10.0) << geometry;
    // The chord speed by central differences (h = 1e-4 s: error ~h²|jerk|/6) at 400 times of the window.
    TrajectoryRequest at = r;
    at.sample_period = 0.0;
    const double h = 1e-4;
    for (int i = 0; i < 400; ++i)
    {
      const double t = out.constant_speed_start + (out.constant_speed_end - out.constant_speed_start) * (i + 0.5) / 400;
      at.sample_times.push_back(t - h);
      at.sample_times.push_back(t + h);
    }
    const TrajectoryResult probe = generate(at, unhurriedLimits());
    double worst = 0.0;
    for (std::size_t i = 0; i + 1 < probe.samples.size(); i += 2)
      worst = std::max(worst, std::abs(chordSpeedByDifferences(probe.samples[i], probe.samples[i + 1], 0.5) / r.speed - 1.0));
    EXPECT_LT(worst, 1e-6) << geometry;
    // ... and by the reported velocities at every sample of the window.
    for (const auto& s : out.samples)
      if (s.time > out.constant_speed_start && s.time < out.constant_speed_end)
      {
        EXPECT_NEAR(std::hypot(s.velocity.linear.norm(), 0.5 * s.velocity.angular.norm()), r.speed, 1e-6 * r.speed)
            << geometry << " t " << s.time;
      }
    // The waypoint times increase to the end, and the motion passes near each corner then.
    ASSERT_EQ(out.waypoint_times.size(), r.waypoints.size());
    for (std::size_t i = 1; i < out.waypoint_times.size(); ++i)
      EXPECT_GT(out.waypoint_times[i], out.waypoint_times[i - 1]) << geometry;
    EXPECT_DOUBLE_EQ(out.waypoint_times.back(), out.duration);
  }
}

TEST(ConstantSpeed, CurvesOfEveryFamilyWithSmoothPathsAreServedWithinTheBounds)
{
  std::mt19937 rng(2804);
  for (const char* curve : { "interpolating", "bspline", "blended", "bezier" })
  {
    TrajectoryRequest r;
    r.waypoints = randomPolygon(rng, 5, 0.5);
    r.curve = curve;
    r.timing = "constant_speed";
    r.speed = 0.05;
    r.max_linear_acceleration = 2.0;
    r.max_angular_acceleration = 4.0;
    // (The geodesic de Boor construction's acceleration may jump at the knots of a rotating B-spline
    // of any degree: with a jerk bound such a path is refused, as tested below for hermite.)
    if (std::string(curve) != "bspline")
    {
      r.max_linear_jerk = 50.0;
      r.max_angular_jerk = 100.0;
    }
    r.sample_period = 1e-3;
    TrajectoryResult out;
    try
    {
      out = generate(r, unhurriedLimits());
    }
    catch (const std::exception& e)
    {
      ADD_FAILURE() << curve << ": " << e.what();
      continue;
    }
    expectWithinBounds(r, out, curve);
    for (const auto& s : out.samples)
      if (s.time > out.constant_speed_start && s.time < out.constant_speed_end)
      {
        EXPECT_NEAR(std::hypot(s.velocity.linear.norm(), s.velocity.angular.norm()), r.speed, 1e-6 * r.speed)
            << curve << " t " << s.time;
      }
  }
}

TEST(ConstantSpeed, WhatCannotBeHeldIsRefusedNamingItsField)
{
  // A bend whose centripetal acceleration V²/r at this speed is over the bound.
  TrajectoryRequest bend = polygon(12, 0.0, 0.05);
  bend.speed = 1.0;
  bend.max_linear_acceleration = 1.0;
  expectRefused(bend, "max_linear_acceleration", "path time");
  // A speed above the velocity bound.
  TrajectoryRequest fast = line(2.0, 0.0);
  fast.speed = 0.5;
  fast.max_linear_velocity = 0.4;
  fast.max_linear_acceleration = 1.0;
  expectRefused(fast, "max_linear_velocity", "path time");
  // The angular speed a rotating path needs at this chord speed.
  TrajectoryRequest turning = line(0.1, 2.0);
  turning.speed = 1.0;
  turning.max_angular_velocity = 0.5;
  turning.max_linear_acceleration = 10.0;
  expectRefused(turning, "max_angular_velocity");
  // A path shorter than its two ramps.
  TrajectoryRequest shorter = line(0.01, 0.0);
  shorter.speed = 1.0;
  shorter.max_linear_acceleration = 1.0;
  expectRefused(shorter, "speed", "ramps");
  // The ramps' bound missing.
  TrajectoryRequest unbounded = line(2.0, 0.0);
  unbounded.speed = 0.5;
  expectRefused(unbounded, "max_linear_acceleration");
  // A corner: an unbounded acceleration at any speed.
  TrajectoryRequest corner = polygon(4, 0.0, 0.0);
  corner.speed = 0.1;
  corner.max_linear_acceleration = 1.0;
  expectRefused(corner, "max_linear_acceleration", "corner");
  // With a jerk bound, a path whose acceleration jumps (hermite is C1).
  TrajectoryRequest c1 = polygon(6, 0.2, 0.0);
  c1.curve = "hermite";
  c1.speed = 0.1;
  c1.max_linear_acceleration = 1.0;
  c1.max_linear_jerk = 10.0;
  expectRefused(c1, "max_linear_jerk", "path time");
  // A clamped end at rest: the path stands still there.
  TrajectoryRequest clamped = polygon(6, 0.2, 0.0);
  clamped.curve = "interpolating";
  clamped.end_condition = "clamped";
  clamped.speed = 0.1;
  clamped.max_linear_acceleration = 1.0;
  expectRefused(clamped, "speed", "stands still");
  // A start state beyond a bound (no recovery under constant_speed).
  TrajectoryRequest moving = line(2.0, 0.0);
  moving.speed = 0.3;
  moving.max_linear_velocity = 0.5;
  moving.max_linear_acceleration = 1.0;
  StartState start;
  start.pose = moving.waypoints[0];
  start.velocity.linear = Eigen::Vector3d(0.8, 0.0, 0.0);
  moving.start_state = start;
  // A start beyond the velocity bound brakes to rest first (B1: 0.8 s at 1 m/s², back within
  // 0.5 m/s after 0.3 s), then ramps to the speed from rest.
  const TrajectoryResult braked = generate(moving, unhurriedLimits());
  EXPECT_NEAR(braked.stop_time, 0.8, 1e-12);
  EXPECT_NEAR(braked.recovery_time, 0.3, 1e-12);
  EXPECT_LT((braked.samples.front().velocity.linear - start.velocity.linear).norm(), 1e-12);
  EXPECT_GT(braked.constant_speed_start, braked.stop_time);
  for (const TrajectorySample& x : braked.samples)
    if (x.time > braked.recovery_time)
    {
      EXPECT_LE(x.velocity.linear.norm(), 0.5 * (1.0 + 1e-6)) << x.time;
      EXPECT_LE(x.acceleration.linear.norm(), 1.0 * (1.0 + 1e-6)) << x.time;
    }
  // Bad speeds: nothing is served.
  for (double bad : { 0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity() })
  {
    TrajectoryRequest r = line(2.0, 0.0);
    r.speed = bad;
    r.max_linear_acceleration = 1.0;
    expectRefused(r, "speed");
  }
}

TEST(ConstantSpeed, AStartStateAtRestStartsTheRampThere)
{
  TrajectoryRequest r = polygon(8, 0.2, 0.15);
  StartState start;
  start.pose = r.waypoints[0];
  start.pose.p += Eigen::Vector3d(0.0, -0.3, 0.0);
  r.start_state = start;
  r.speed = 0.2;
  r.max_linear_acceleration = 1.0;
  r.sample_period = 1e-3;
  const TrajectoryResult out = generate(r, unhurriedLimits());
  EXPECT_LT((out.samples.front().pose.p - start.pose.p).norm(), 1e-12);
  expectWithinBounds(r, out, "start at rest");
  EXPECT_GT(out.constant_speed_end, out.constant_speed_start);
}

// A replan from a moving state: the first sample is the start state (pose, velocity and
// acceleration), the ramp takes its chord speed to `speed` within the bounds, and the window holds
// it; faster and slower starts than the speed, on both geometries.
TEST(ConstantSpeed, AMovingStartRampsFromItsStateToTheSpeed)
{
  for (const char* geometry : { "double_geodesic", "screw" })
    for (double v0 : { 0.05, 0.3 })
    {
      TrajectoryRequest r = polygon(8, 0.2, 0.15);
      r.geometry = geometry;
      StartState start;
      start.pose = r.waypoints[0];
      start.pose.p += Eigen::Vector3d(0.0, -0.3, 0.0);
      start.velocity.linear = Eigen::Vector3d(0.2, 0.5, 0.0).normalized() * v0;
      start.velocity.angular = Eigen::Vector3d(0.0, 0.0, 0.02);
      start.acceleration.linear = Eigen::Vector3d(0.05, -0.02, 0.0);
      r.start_state = start;
      r.speed = 0.15;
      r.max_linear_velocity = 0.5;
      r.max_linear_acceleration = 1.0;
      r.max_linear_jerk = 20.0;
      r.sample_period = 1e-3;
      const std::string what = std::string(geometry) + " v0 " + std::to_string(v0);
      const TrajectoryResult out = generate(r, unhurriedLimits());
      const TrajectorySample& first = out.samples.front();
      EXPECT_LT((first.pose.p - start.pose.p).norm(), 1e-12) << what;
      EXPECT_LT((first.velocity.linear - start.velocity.linear).norm(), 1e-9) << what;
      EXPECT_LT((first.velocity.angular - start.velocity.angular).norm(), 1e-9) << what;
      EXPECT_LT((first.acceleration.linear - start.acceleration.linear).norm(), 1e-7) << what;
      for (const auto& s : out.samples)
        if (s.time > out.constant_speed_start && s.time < out.constant_speed_end)
        {
          EXPECT_NEAR(std::hypot(s.velocity.linear.norm(), s.velocity.angular.norm()), r.speed, 1e-6 * r.speed)
              << what << " t " << s.time;
        }
      // Within the bounds throughout; rest at the end only.
      for (const auto& s : out.samples)
      {
        EXPECT_LE(s.velocity.linear.norm(), 0.5 * (1 + 1e-6)) << what;
        EXPECT_LE(s.acceleration.linear.norm(), 1.0 * (1 + 1e-6)) << what;
      }
      EXPECT_LT(out.samples.back().velocity.linear.norm(), 1e-9) << what;
      EXPECT_GT(out.constant_speed_end, out.constant_speed_start + 5.0) << what;
    }
}

TEST(ConstantSpeed, OtherTimingsDoNotReadSpeedButRefuseBadValues)
{
  TrajectoryRequest r = line(2.0, 0.0);
  r.timing = "stretch";
  r.speed = 0.3;
  const TrajectoryResult out = generate(r, unhurriedLimits());
  EXPECT_EQ(out.constant_speed_start, 0.0);
  EXPECT_EQ(out.constant_speed_end, 0.0);
  r.speed = -1.0;
  expectRefused(r, "speed");
}

// Uneven waypoint times put a bend of a few millimetres (a near half-turn in 0.03 s between
// segments of 30 s) in a piece of the check metres long in chord length: the request-space grid's
// interpolating/natural screw constant_speed/al N=5 times=uneven start=resting was served with
// 4 times max_linear_acceleration there, between the check's points. The table of S(σ) halves its
// intervals around such a bend, and its halvings are the check's piece ends too: refused, naming
// the bound and the bend, and served within the bound at a speed that passes it.
TEST(ConstantSpeed, ABendOfAFewMillimetresBetweenUnevenTimesIsChecked)
{
  TrajectoryRequest r;
  auto pose = [](double x, double y, double z, double qx, double qy, double qz, double qw) {
    return Pose<double>(Quaternion<double>(qw, qx, qy, qz), Eigen::Vector3d(x, y, z));
  };
  r.waypoints = {
    pose(0.34312178463589427, -0.35324395021084432, 1.490933618866159, 0.17162881559849935, -0.13051072393472751,
         0.12114915357260614, 0.96893414801158229),
    pose(0.66439570294720218, -0.48640724710442801, 1.3529096869799446, 0.116005420325876, -0.0015382964152547782,
         0.062199647894463042, 0.99129792691246987),
    pose(0.21081333107022127, 0.32861885485813253, 0.75209484116695113, 0.41620646670839972, 0.24037328057043064,
         -0.87689288392424525, 0.0071925781844325775),
    pose(1.3590015745859052, -0.11833111075377795, 1.1817239462879314, 0.41620646653090632, 0.24037328049141635,
         -0.8768928840264647, 0.0071925786336586202),
    pose(1.9116803475683204, 0.087111175822422893, 2.2845675635249938, 0.41620646653090637, 0.24037328049141637,
         -0.87689288402646481, 0.0071925786336586211),
    pose(3.4303076614354224, 0.22184935110643128, 1.7569950836096861, 0.35831864911151651, 0.40089140686239078,
         -0.83373495729047564, 0.12561785937771558),
  };
  r.times = { 0.0, 0.7, 0.73162277660168373, 32.354399378285478, 35.869561477918417, 36.055075573965603 };
  r.curve = "interpolating";
  r.geometry = "screw";
  r.timing = "constant_speed";
  r.speed = 0.1;
  r.max_linear_acceleration = 0.5;
  expectRefused(r, "max_linear_acceleration", "the bend's centripetal share");
  // The centripetal share grows with V²: about 29 times the bound at 0.1 m/s, within it at 0.015.
  r.speed = 0.015;
  r.sample_count = 20001;
  const TrajectoryResult out = generate(r, unhurriedLimits());
  expectWithinBounds(r, out, "at 0.015 m/s");
  // Independently of the reported accelerations, where the bend is (path time 0.403 s, between the
  // first two waypoints): second differences of the positions at 40 000 steps between the times
  // the motion passes them (9 µm of chord per step at this speed).
  ASSERT_GE(out.waypoint_times.size(), 2u);
  const double t0 = out.waypoint_times[0], t1 = out.waypoint_times[1];
  const int steps = 40000;
  const double h = (t1 - t0) / steps;
  double worst = 0.0;
  for (int k = 1; k < steps; ++k)
  {
    const double t = t0 + k * h;
    const Eigen::Vector3d d2 =
        (out.state_at(t + h).pose.p - 2.0 * out.state_at(t).pose.p + out.state_at(t - h).pose.p) / (h * h);
    worst = std::max(worst, d2.norm());
  }
  EXPECT_LE(worst, 0.5 * (1.0 + 1e-3)) << "second differences between " << t0 << " and " << t1 << " s";
  EXPECT_GT(worst, 0.1) << "the bend's centripetal acceleration is seen";
}
