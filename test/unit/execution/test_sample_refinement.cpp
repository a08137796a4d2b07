// Tests of execution/sample_refinement.h through the planner (the request's sample_tolerance): the
// samples it serves, sent as an action goal (GoalTrajectory, the node's own interpolation and
// check), are accepted where the sparse samples alone are refused, and the goal's motion is checked
// by brute force against the motion itself (result.state_at) — its pose within the tolerance and
// its rates within the bounds at many points of every segment, not only at the middles the
// refinement tests. Also: where no sampling can help (an acceleration that jumps) the refinement
// stops after a few halvings; turns of more than half a turn between two samples are followed; the
// budget is ~max_samples; the field is validated; streaming gives the same samples.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "se3_interpolation/execution/goal_trajectory.h"
#include "se3_interpolation/execution/sample_refinement.h"
#include "se3_interpolation/planner/planner.h"
#include "test_utils.h"

namespace se3_interpolation
{
namespace
{
Pose<double> poseAt(const Eigen::Vector3d& p, const Eigen::Vector3d& axis, double angle)
{
  Pose<double> x;
  x.p = p;
  x.q = Quaternion<double>(Eigen::AngleAxisd(angle, axis.normalized()));
  return x;
}

/// The chord distance of the refinement, written out here: √(|Δp|² + ρ² θ²).
double chord(const Pose<double>& a, const Pose<double>& b, double rho)
{
  const double theta = a.q.angularDistance(b.q);
  return std::sqrt((a.p - b.p).squaredNorm() + rho * rho * theta * theta);
}

std::vector<GoalPoint> pointsOf(const TrajectoryResult& result)
{
  std::vector<GoalPoint> points;
  for (const TrajectorySample& s : result.samples)
  {
    GoalPoint p;
    p.time_from_start = s.time;
    p.pose = s.pose;
    p.velocity = s.velocity;
    p.acceleration = s.acceleration;
    points.push_back(p);
  }
  return points;
}

/// What brute force finds of the goal made of `result`'s samples: the largest chord distance from
/// the motion and each rate's largest ratio to its bound, at `per_segment` evenly spaced points of
/// every segment (both ends included).
struct BruteForce
{
  double deviation = 0.0;
  double ratio[4] = { 0.0, 0.0, 0.0, 0.0 };
};

BruteForce bruteForce(const TrajectoryRequest& r, const TrajectoryResult& result, GeometryType geometry,
                      int per_segment = 40)
{
  const GoalTrajectory goal(pointsOf(result), geometry);
  const double bounds[4] = { r.max_linear_velocity, r.max_angular_velocity, r.max_linear_acceleration,
                             r.max_angular_acceleration };
  const double rho = r.rotation_scale > 0.0 ? r.rotation_scale : 1.0;
  BruteForce b;
  for (std::size_t i = 0; i + 1 < result.samples.size(); ++i)
  {
    const double ta = result.samples[i].time, tb = result.samples[i + 1].time;
    for (int k = 0; k <= per_segment; ++k)
    {
      const double t = ta + (tb - ta) * k / per_segment;
      const TrajectorySample g = goal.stateAt(t);
      const TrajectorySample m = result.state_at(t);
      b.deviation = std::max(b.deviation, chord(g.pose, m.pose, rho));
      const double rates[4] = { g.velocity.linear.norm(), g.velocity.angular.norm(), g.acceleration.linear.norm(),
                                g.acceleration.angular.norm() };
      for (int j = 0; j < 4; ++j)
        if (bounds[j] > 0.0)
          b.ratio[j] = std::max(b.ratio[j], rates[j] / bounds[j]);
    }
  }
  return b;
}

/// A motion through four poses turning about several axes, jerk-limited rest to rest.
TrajectoryRequest jerkLimitedRequest(const std::string& geometry, double scale)
{
  TrajectoryRequest r;
  r.waypoints = { poseAt({ 0, 0, 0 }, { 0, 0, 1 }, 0.0), poseAt({ 1, 0.5, 0 }, { 0, 1, 1 }, 0.8),
                  poseAt({ 2, 0, 0.5 }, { 1, 0, 0 }, 0.3), poseAt({ 3, 1, 0.5 }, { 1, 1, 0 }, -0.5) };
  r.geometry = geometry;
  r.timing = "time_optimal";
  // `scale` slows everything down: velocity × s, acceleration × s², jerk × s³, so the motion lasts
  // 1/s times as long and the same number of samples lie 1/s times as far apart.
  r.max_linear_velocity = 0.5 * scale;
  r.max_angular_velocity = 1.0 * scale;
  r.max_linear_acceleration = 1.0 * scale * scale;
  r.max_angular_acceleration = 2.0 * scale * scale;
  r.max_linear_jerk = 10.0 * scale * scale * scale;
  r.max_angular_jerk = 20.0 * scale * scale * scale;
  r.sample_count = 8;
  return r;
}

void expectOrderedAndSignContinuous(const TrajectoryResult& result, const std::vector<double>& base_times)
{
  for (std::size_t i = 1; i < result.samples.size(); ++i)
  {
    EXPECT_GT(result.samples[i].time, result.samples[i - 1].time) << i;
    EXPECT_GE(result.samples[i].pose.q.coeffs().dot(result.samples[i - 1].pose.q.coeffs()), 0.0) << i;
  }
  // Every sample asked for is still there, at its time.
  std::size_t j = 0;
  for (double t : base_times)
  {
    while (j < result.samples.size() && result.samples[j].time < t)
      ++j;
    ASSERT_LT(j, result.samples.size());
    EXPECT_EQ(result.samples[j].time, t);
  }
}

TEST(SampleRefinement, SparseJerkLimitedSamplesAreRefusedAndRefinedOnesExecuteTheMotion)
{
  const double tolerance = 1e-3;
  std::mt19937 rng(29);
  for (const std::string geometry : { "double_geodesic", "screw" })
    for (double scale : { 1.0, 0.01, 0.0 })
    {
      SCOPED_TRACE(geometry + ", bounds scaled by " + std::to_string(scale));
      // scale 0: thirty random poses at the bounds of 0.01, still 8 samples (one per 4 waypoints).
      TrajectoryRequest r = jerkLimitedRequest(geometry, scale > 0.0 ? scale : 0.01);
      if (scale == 0.0)
        r.waypoints = test::randomPolygon(rng, 30, 0.8);
      const GeometryType g = geometry == "screw" ? GeometryType::kScrew : GeometryType::kDoubleGeodesic;
      const TrajectoryResult sparse = generate(r, test::unhurriedLimits());
      ASSERT_EQ(sparse.samples.size(), 8u);
      // The sparse samples, as a goal, are refused by the node's check (a test that could not fail
      // without the option proves nothing about it).
      EXPECT_THROW(GoalTrajectory(pointsOf(sparse), g).checkLimits(motionLimitsOf(r), kGoalLimitTolerance), InvalidGoalError);
      const BruteForce before = bruteForce(r, sparse, g);
      EXPECT_GT(before.deviation, tolerance);

      r.sample_tolerance = tolerance;
      const TrajectoryResult refined = generate(r, test::unhurriedLimits());
      std::vector<double> base;
      for (const TrajectorySample& s : sparse.samples)
        base.push_back(s.time);
      expectOrderedAndSignContinuous(refined, base);
      EXPECT_GT(refined.samples.size(), 8u);
      const GoalTrajectory goal(pointsOf(refined), g);
      EXPECT_NO_THROW(goal.checkLimits(motionLimitsOf(r), kGoalLimitTolerance));
      EXPECT_NO_THROW(goal.requireEndsAtRest());
      const BruteForce after = bruteForce(r, refined, g);
      // The refinement tests the middles, where the quintic's error τ³(h − τ)³ of a smooth motion
      // peaks; elsewhere the brute force may find a little more.
      EXPECT_LT(after.deviation, 1.5 * tolerance);
      for (int j = 0; j < 4; ++j)
        EXPECT_LT(after.ratio[j], 1.0 + kGoalLimitTolerance) << j;
      std::cout << geometry << " x" << scale << ": " << sparse.samples.size() << " -> " << refined.samples.size()
                << " samples, deviation " << before.deviation << " -> " << after.deviation << ", velocity ratio "
                << before.ratio[0] << " -> " << after.ratio[0] << ", acceleration ratio " << before.ratio[2] << " -> "
                << after.ratio[2] << "\n";
    }
}

TEST(SampleRefinement, AnAccelerationThatJumpsStopsTheRefinementWithinAFewHalvings)
{
  // time_optimal without a jerk bound: bang-bang accelerations, which the quintic overshoots by a
  // fixed fraction however dense the samples (goal_trajectory.h). The velocity is continuous, so it
  // and the pose converge; the acceleration's excess does not, and the refinement gives up on it
  // after kExcessPatience halvings at each switch instead of halving down to kMinSampleSpacing.
  for (const std::string geometry : { "double_geodesic", "screw" })
  {
    SCOPED_TRACE(geometry);
    TrajectoryRequest r = jerkLimitedRequest(geometry, 1.0);
    r.max_linear_jerk = 0.0;
    r.max_angular_jerk = 0.0;
    r.sample_count = 16;
    r.sample_tolerance = 1e-3;
    const GeometryType g = geometry == "screw" ? GeometryType::kScrew : GeometryType::kDoubleGeodesic;
    const TrajectoryResult refined = generate(r, test::unhurriedLimits());
    const BruteForce after = bruteForce(r, refined, g);
    EXPECT_LT(after.deviation, 1.5 * r.sample_tolerance);
    EXPECT_LT(after.ratio[0], 1.0 + kGoalLimitTolerance);
    EXPECT_LT(after.ratio[1], 1.0 + kGoalLimitTolerance);
    // Halving to 1 µs at every switch of this 9-s motion would insert ~20 samples per switch and
    // side; a handful per switch is what giving up after kExcessPatience futile halvings leaves.
    const double shortest = [&] {
      double h = 1e300;
      for (std::size_t i = 1; i < refined.samples.size(); ++i)
        h = std::min(h, refined.samples[i].time - refined.samples[i - 1].time);
      return h;
    }();
    EXPECT_GT(shortest, 1e-3);
    EXPECT_LT(refined.samples.size(), 400u);
    std::cout << geometry << ": " << refined.samples.size() << " samples, shortest interval " << shortest
              << " s, acceleration ratio " << after.ratio[2] << "\n";
  }
}

TEST(SampleRefinement, TurnsOfMoreThanHalfATurnBetweenSamplesAreFollowed)
{
  // Three turns about z in 8 s; two samples (both ends) are 18.85 rad apart, of which a goal through
  // them alone takes the short way. Refined, the goal turns with the motion.
  TrajectoryRequest r;
  for (int i = 0; i <= 8; ++i)
    r.waypoints.push_back(poseAt({ 0.1 * i, 0, 0 }, { 0, 0, 1 }, i * 0.75 * M_PI));
  r.end_condition = "clamped";
  r.sample_count = 2;
  for (const std::string geometry : { "double_geodesic", "screw" })
  {
    SCOPED_TRACE(geometry);
    r.geometry = geometry;
    const GeometryType g = geometry == "screw" ? GeometryType::kScrew : GeometryType::kDoubleGeodesic;
    r.sample_tolerance = 0.0;
    const TrajectoryResult sparse = generate(r, test::unhurriedLimits());
    EXPECT_GT(bruteForce(r, sparse, g).deviation, 1.0);
    r.sample_tolerance = 1e-4;
    const TrajectoryResult refined = generate(r, test::unhurriedLimits());
    expectOrderedAndSignContinuous(refined, { sparse.samples.front().time, sparse.samples.back().time });
    EXPECT_LT(bruteForce(r, refined, g, 100).deviation, 1.5 * r.sample_tolerance);
  }
}

TEST(SampleRefinement, TheBudgetIsTheSampleLimit)
{
  TrajectoryRequest r = jerkLimitedRequest("screw", 0.01);
  r.sample_tolerance = 1e-9;
  PlannerLimits limits = test::unhurriedLimits();
  limits.max_samples = 200;
  try
  {
    generate(r, limits);
    FAIL() << "a refinement past max_samples was served";
  }
  catch (const LimitExceededError& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("sample_tolerance: ", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("~max_samples"), std::string::npos) << e.what();
  }
  // The same request within a limit that suffices is served, and keeps to it.
  limits.max_samples = 200000;
  EXPECT_LE(generate(r, limits).samples.size(), limits.max_samples);
}

TEST(SampleRefinement, TheFieldIsValidated)
{
  for (double bad : { -1e-3, std::nan(""), std::numeric_limits<double>::infinity() })
  {
    TrajectoryRequest r = jerkLimitedRequest("screw", 1.0);
    r.sample_tolerance = bad;
    try
    {
      generate(r, test::unhurriedLimits());
      FAIL() << bad;
    }
    catch (const InvalidInputError& e)
    {
      EXPECT_EQ(std::string(e.what()).rfind("sample_tolerance: ", 0), 0u) << e.what();
    }
  }
  SphereRequest s;
  s.waypoints = { Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1) };
  s.sample_tolerance = 1e-3;
  try
  {
    generate(s, test::unhurriedLimits());
    FAIL() << "sample_tolerance on the sphere";
  }
  catch (const InvalidInputError& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("sample_tolerance: ", 0), 0u) << e.what();
  }
}

TEST(SampleRefinement, StreamingGivesTheSameSamples)
{
  // Enough base samples, and refinement, to span more than one of the sink's blocks (kSamplesPerBlock).
  TrajectoryRequest r = jerkLimitedRequest("screw", 0.01);
  r.sample_count = 1500;
  r.sample_tolerance = 1e-12;
  const TrajectoryResult kept = generate(r, test::unhurriedLimits());
  ASSERT_GT(kept.samples.size(), kSamplesPerBlock);
  ASSERT_GT(kept.samples.size(), r.sample_count);
  std::cout << kept.samples.size() << " samples\n";
  std::vector<TrajectorySample> streamed;
  const SampleSink<PoseSpace> sink = [&streamed](const TrajectorySample* first, std::size_t count) {
    streamed.insert(streamed.end(), first, first + count);
  };
  generate(r, test::unhurriedLimits(), sink);
  ASSERT_EQ(streamed.size(), kept.samples.size());
  for (std::size_t i = 0; i < streamed.size(); ++i)
  {
    EXPECT_EQ(streamed[i].time, kept.samples[i].time) << i;
    EXPECT_EQ(streamed[i].pose.q.coeffs(), kept.samples[i].pose.q.coeffs()) << i;
  }
}

}  // namespace
}  // namespace se3_interpolation
