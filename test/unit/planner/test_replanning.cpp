// Replanning from every state of a played motion (planner/start_state.cpp): from every 10 ms of
// a jerk-limited and an acceleration-limited motion, and every 50 ms of motions of every curve
// family (both geometries, uneven times), towards targets ahead, sideways and behind. Every replan
// is served, starts exactly in the state, keeps every bound on its samples (after a reported
// recovery), reaches its target, and is no longer than braking to rest and going from there.
//
// The brake-and-go bound is the test's own (request_space.h, brakeAndGoBound, which the
// request-space grid and sweep check too): a valid brake of each channel written in the test and the
// planner's motion from rest at the start pose. Under the sanitizers every fifth state is replanned.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/planner.h"
#include "request_space.h"
#include "test_utils.h"

namespace se3_interpolation
{
namespace
{
constexpr double kSwitchTolerance = 1e-9;
constexpr double kBoundTolerance = 1e-6;

Pose<double> pose(const Eigen::Vector3d& p, double angle, const Eigen::Vector3d& axis)
{
  return Pose<double>(Quaternion<double>(Eigen::AngleAxisd(angle, axis.normalized())), p);
}

struct Bounds
{
  double v = 1.0, w = 2.0, a = 2.0, alpha = 4.0, j = 0.0, jw = 0.0;
};

void applyBounds(const Bounds& b, TrajectoryRequest* r)
{
  r->timing = "time_optimal";
  r->max_linear_velocity = b.v;
  r->max_angular_velocity = b.w;
  r->max_linear_acceleration = b.a;
  r->max_angular_acceleration = b.alpha;
  r->max_linear_jerk = b.j;
  r->max_angular_jerk = b.jw;
}

struct Tally
{
  int tried = 0;
  double worst_duration_ratio = 0.0;
  double worst_length_ratio = 0.0;
};

/// One replan from `x` (a sample of a played motion) to `target`, checked against every promise.
void checkReplan(TrajectoryRequest r, const TrajectorySample& x, const Bounds& b, Tally* tally)
{
  StartState s;
  s.pose = x.pose;
  s.velocity = x.velocity;
  s.acceleration = x.acceleration;
  r.start_state = s;
  r.sample_count = 300;
  ++tally->tried;
  TrajectoryResult out;
  try
  {
    out = generate(r, test::unhurriedLimits());
  }
  catch (const InterpolationError& e)
  {
    ADD_FAILURE() << "refused: " << e.what();
    return;
  }
  const TrajectorySample& first = out.samples.front();
  EXPECT_LT((first.pose.p - s.pose.p).norm(), kSwitchTolerance);
  EXPECT_LT(test::poseDistance(first.pose, s.pose), kSwitchTolerance);
  EXPECT_LT((first.velocity.linear - s.velocity.linear).norm(), kSwitchTolerance);
  EXPECT_LT((first.velocity.angular - s.velocity.angular).norm(), kSwitchTolerance);
  EXPECT_LT((first.acceleration.linear - s.acceleration.linear).norm(), kSwitchTolerance);
  EXPECT_LT((first.acceleration.angular - s.acceleration.angular).norm(), kSwitchTolerance);
  EXPECT_LT(test::poseDistance(out.samples.back().pose, r.waypoints.back()), 1e-6);
  for (std::size_t i = 0; i < out.samples.size(); ++i)
  {
    const TrajectorySample& y = out.samples[i];
    if (y.time <= out.recovery_time)
      continue;
    EXPECT_LE(y.velocity.linear.norm(), b.v * (1.0 + kBoundTolerance)) << y.time;
    EXPECT_LE(y.velocity.angular.norm(), b.w * (1.0 + kBoundTolerance)) << y.time;
    EXPECT_LE(y.acceleration.linear.norm(), b.a * (1.0 + kBoundTolerance)) << y.time;
    EXPECT_LE(y.acceleration.angular.norm(), b.alpha * (1.0 + kBoundTolerance)) << y.time;
    // With a jerk bound the acceleration is continuous and changes by at most J dt (mean value).
    if (b.j > 0.0 && i > 0 && out.samples[i - 1].time > out.recovery_time)
    {
      const TrajectorySample& p = out.samples[i - 1];
      const double dt = y.time - p.time;
      EXPECT_LE((y.acceleration.linear - p.acceleration.linear).norm(), b.j * dt * (1.0 + 1e-6) + 1e-9) << y.time;
      EXPECT_LE((y.acceleration.angular - p.acceleration.angular).norm(), b.jw * dt * (1.0 + 1e-6) + 1e-9)
          << y.time;
    }
  }
  // The brake-and-go bound (request_space.h).
  const test::BrakeAndGo bound = test::brakeAndGoBound(r, test::unhurriedLimits());
  EXPECT_LE(out.duration, bound.duration * (1.0 + 1e-9))
      << "braked for " << out.stop_time << " s; start |v| " << s.velocity.linear.norm() << ", |w| "
      << s.velocity.angular.norm() << ", |a| " << s.acceleration.linear.norm() << ", |alpha| "
      << s.acceleration.angular.norm();
  EXPECT_LE(test::chordLength(r, out.figures), bound.length * (1.0 + 1e-9));
  tally->worst_duration_ratio = std::max(tally->worst_duration_ratio, out.duration / bound.duration);
  tally->worst_length_ratio = std::max(tally->worst_length_ratio, test::chordLength(r, out.figures) / bound.length);
}

/// Targets ahead of, beside and behind a motion from `from` to `to`.
std::vector<Pose<double>> targets(const Pose<double>& from, const Pose<double>& to)
{
  const Eigen::Vector3d d = to.p - from.p;
  const Eigen::Vector3d side = d.cross(Eigen::Vector3d::UnitZ()).normalized() * d.norm();
  return { pose(to.p + 0.5 * d, 0.9, { 0, 0, 1 }), pose(from.p + 0.5 * d + side, -0.4, { 1, 0, 0 }),
           pose(from.p - 0.7 * d, 2.0, { 0, 1, 1 }) };
}

/// Replans from every `step`-th 10 ms sample of `played` to the targets (all of them, or one in
/// turn with `rotate`).
void replanAlong(const TrajectoryRequest& played_request, const Bounds& b, std::size_t step, bool rotate,
                 Tally* tally)
{
  if (test::kSanitized)
    step *= 5;
  TrajectoryRequest first = played_request;
  applyBounds(b, &first);
  first.sample_period = 0.01;
  const TrajectoryResult played = generate(first, test::unhurriedLimits());
  const std::vector<Pose<double>> goals = targets(first.waypoints.front(), first.waypoints.back());
  for (std::size_t i = 1; i + 1 < played.samples.size(); i += step)
    for (std::size_t k = 0; k < goals.size(); ++k)
    {
      if (rotate && k != (i / step) % goals.size())
        continue;
      SCOPED_TRACE("replan at t = " + std::to_string(played.samples[i].time) + " to target " + std::to_string(k));
      TrajectoryRequest r;
      r.waypoints = { goals[k] };
      r.geometry = played_request.geometry;
      applyBounds(b, &r);
      checkReplan(r, played.samples[i], b, tally);
    }
}

TrajectoryRequest straightMove()
{
  TrajectoryRequest r;
  r.waypoints = { pose({ 0.0, 0.0, 0.3 }, 0.0, { 0, 0, 1 }), pose({ 1.2, -0.4, 0.6 }, -0.5, { 0, 0, 1 }) };
  r.curve = "piecewise_geodesic";
  return r;
}

Bounds jerkBounds()
{
  Bounds b;
  b.j = 20.0;
  b.jw = 40.0;
  return b;
}

TEST(Replanning, EveryTenMillisecondsOfAJerkLimitedMove)
{
  Tally tally;
  replanAlong(straightMove(), jerkBounds(), 1, false, &tally);
  std::cout << tally.tried << " replans; worst duration " << tally.worst_duration_ratio << ", length "
            << tally.worst_length_ratio << " of the brake-and-go bound\n";
  EXPECT_GT(tally.tried, test::kSanitized ? 100 : 500);
}

TEST(Replanning, EveryTenMillisecondsOfAnAccelerationLimitedMove)
{
  Tally tally;
  replanAlong(straightMove(), Bounds(), 1, false, &tally);
  std::cout << tally.tried << " replans; worst duration " << tally.worst_duration_ratio << ", length "
            << tally.worst_length_ratio << " of the brake-and-go bound\n";
  EXPECT_GT(tally.tried, test::kSanitized ? 100 : 500);
}

TEST(Replanning, EveryFamilyBothGeometriesUnevenTimes)
{
  const std::vector<Pose<double>> waypoints = { pose({ 0.0, 0.0, 0.3 }, 0.0, { 0, 0, 1 }),
                                                pose({ 0.3, 0.2, 0.4 }, 0.8, { 1, 1, 0 }),
                                                pose({ 1.0, -0.3, 0.6 }, -0.6, { 0, 0, 1 }),
                                                pose({ 1.1, 0.5, 0.2 }, 1.5, { 0, 1, 0 }) };
  Tally tally;
  for (const std::string curve : { "interpolating", "bspline", "blended", "hermite", "piecewise_geodesic" })
    for (const std::string geometry : { "double_geodesic", "screw" })
      for (bool jerk : { false, true })
      {
        SCOPED_TRACE(curve + " " + geometry + (jerk ? " jerk" : ""));
        TrajectoryRequest r;
        r.waypoints = waypoints;
        r.curve = curve;
        r.geometry = geometry;
        if (curve == "piecewise_geodesic")
          r.blend_radius = 0.1;
        else
          r.times = { 0.0, 0.4, 3.0, 3.4 };
        replanAlong(r, jerk ? jerkBounds() : Bounds(), 5, true, &tally);
      }
  std::cout << tally.tried << " replans; worst duration " << tally.worst_duration_ratio << ", length "
            << tally.worst_length_ratio << " of the brake-and-go bound\n";
}

// The case that went 85 m: 1 ms before the end of a jerk-limited move (speed 5e-6 m/s, braking at
// 0.01 m/s²), a target 0.87 m away. It must be no longer than braking and going from rest.
TEST(Replanning, NearTheEndOfABrakingMoveGoesStraightThere)
{
  TrajectoryRequest first = straightMove();
  applyBounds(jerkBounds(), &first);
  first.sample_times = {};
  const TrajectoryResult played = generate(first, test::unhurriedLimits());
  const double end = played.duration;
  for (double before : { 1e-3, 1e-2, 3e-2 })
  {
    SCOPED_TRACE("before the end: " + std::to_string(before));
    const TrajectorySample x = played.state_at(end - before);
    EXPECT_LT(x.velocity.linear.norm(), 0.05);
    TrajectoryRequest r;
    r.waypoints = { pose({ 0.5, 0.2, 0.9 }, 0.3, { 0, 0, 1 }) };
    applyBounds(jerkBounds(), &r);
    Tally tally;
    checkReplan(r, x, jerkBounds(), &tally);
    StartState s{ x.pose, x.velocity, x.acceleration };
    r.start_state = s;
    const TrajectoryResult out = generate(r, test::unhurriedLimits());
    TrajectoryRequest rest = r;
    rest.start_state = StartState{ x.pose, Twist{}, Twist{} };
    const TrajectoryResult from_rest = generate(rest, test::unhurriedLimits());
    EXPECT_LT(out.duration, from_rest.duration + 0.1);
    EXPECT_LT(out.figures.length, from_rest.figures.length + 0.01);
  }
}
}  // namespace
}  // namespace se3_interpolation
