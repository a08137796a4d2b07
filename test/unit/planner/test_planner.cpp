// planner/planner.h: requests through the planner with interpolating and Hermite curves: the
// waypoints are passed, request twists reach the curve, stretching meets each bound, waypoint
// times follow the parameterisation, and errors name the field.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/planner/validation.h"
#include "spline_test_utils.h"
#include "test_utils.h"

using namespace se3_interpolation;
using namespace se3_interpolation::test;

// ---- the planner: requests, timing, stretching ----------------------------------------------

namespace
{
TrajectoryRequest requestThrough(const std::vector<Pose<double>>& x, const std::string& curve)
{
  TrajectoryRequest r;
  r.waypoints = x;
  r.curve = curve;
  return r;
}
}  // namespace

TEST(Planner, InterpolatingAndHermiteRequestsPassTheirWaypoints)
{
  std::mt19937 rng(170);
  const std::vector<Pose<double>> x = randomPolygon(rng, 7);
  const std::vector<double> t = randomTimes(rng, 7);
  for (const char* geometry : { "screw", "double_geodesic" })
    for (const char* curve : { "interpolating", "hermite" })
    {
      TrajectoryRequest r = requestThrough(x, curve);
      r.geometry = geometry;
      r.times = t;
      r.sample_times = t;
      const TrajectoryResult out = generate(r, test::unhurriedLimits());
      for (std::size_t i = 0; i < x.size(); ++i)
        EXPECT_LT(poseDistance(out.samples[i].pose, x[i]), 1e-10) << geometry << " " << curve << " " << i;
    }
}

TEST(Planner, ASampleSinkGetsTheSamplesGenerateKeepsInBlocksAndNothingBeforeAnError)
{
  // Several turns about z: the quaternion's sign follows from sample to sample across the blocks.
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  std::vector<Pose<double>> x;
  for (int i = 0; i < 9; ++i)
    x.emplace_back(so3Exp<double>(Eigen::Vector3d(2.5 * i * z)), Eigen::Vector3d(0.3 * i, std::sin(i), 0.0));
  for (const char* geometry : { "screw", "double_geodesic" })
  {
    TrajectoryRequest r = requestThrough(x, "interpolating");
    r.geometry = geometry;
    r.sample_count = 3 * kSamplesPerBlock + 17;
    const TrajectoryResult kept = generate(r, test::unhurriedLimits());
    std::vector<TrajectorySample> streamed;
    std::vector<std::size_t> blocks;
    const TrajectoryResult out =
        generate(r, test::unhurriedLimits(), SampleSink<PoseSpace>([&](const TrajectorySample* first, std::size_t n) {
                   blocks.push_back(n);
                   streamed.insert(streamed.end(), first, first + n);
                 }));
    EXPECT_TRUE(out.samples.empty());
    EXPECT_EQ(out.duration, kept.duration);
    EXPECT_EQ(blocks, (std::vector<std::size_t>{ kSamplesPerBlock, kSamplesPerBlock, kSamplesPerBlock, 17 }));
    ASSERT_EQ(streamed.size(), kept.samples.size()) << geometry;
    // A block that starts with w < 0 takes its sign from the block before (alone, it would start
    // with w >= 0, the sign nearest the identity): the continuity across blocks is exercised.
    bool sign_carried = false;
    for (std::size_t b = kSamplesPerBlock; b < kept.samples.size(); b += kSamplesPerBlock)
      sign_carried = sign_carried || kept.samples[b].pose.q.w() < 0.0;
    EXPECT_TRUE(sign_carried) << geometry;
    for (std::size_t i = 0; i < streamed.size(); ++i)
    {
      ASSERT_EQ(streamed[i].time, kept.samples[i].time) << geometry << " " << i;
      ASSERT_EQ(streamed[i].pose.q.coeffs(), kept.samples[i].pose.q.coeffs()) << geometry << " " << i;
      ASSERT_EQ(streamed[i].pose.p, kept.samples[i].pose.p) << geometry << " " << i;
      ASSERT_EQ(streamed[i].acceleration.angular, kept.samples[i].acceleration.angular) << geometry << " " << i;
    }
    r.max_linear_velocity = -1.0;
    bool called = false;
    EXPECT_THROW(generate(r, test::unhurriedLimits(),
                          SampleSink<PoseSpace>([&](const TrajectorySample*, std::size_t) { called = true; })),
                 InvalidInputError);
    EXPECT_FALSE(called);
  }
}

TEST(Planner, RequestTwistsReachTheCurve)
{
  std::mt19937 rng(171);
  const std::vector<Pose<double>> x = randomPolygon(rng, 5);
  const std::vector<double> t = randomTimes(rng, 5);
  for (const char* geometry : { "screw", "double_geodesic" })
  {
    TrajectoryRequest r = requestThrough(x, "interpolating");
    r.geometry = geometry;
    r.times = t;
    r.sample_times = { t.front(), t.back() };
    r.end_condition = "clamped";
    r.start_velocity = randomTwist(rng, 0.5);
    r.end_velocity = randomTwist(rng, 0.5);
    TrajectoryResult out = generate(r, test::unhurriedLimits());
    EXPECT_LT(twistError(out.samples.front().velocity, r.start_velocity), 1e-9) << geometry;
    EXPECT_LT(twistError(out.samples.back().velocity, r.end_velocity), 1e-9) << geometry;

    r.curve = "hermite";
    r.sample_times = t;
    for (std::size_t i = 0; i < x.size(); ++i)
      r.velocities.push_back(randomTwist(rng, 0.5));
    out = generate(r, test::unhurriedLimits());
    for (std::size_t i = 0; i < x.size(); ++i)
      EXPECT_LT(twistError(out.samples[i].velocity, r.velocities[i]), 1e-9) << geometry << " " << i;
  }
}

TEST(Planner, StretchingMeetsEachBoundWithinOnePercentAndNeverExceedsIt)
{
  std::mt19937 rng(172);
  const std::vector<Pose<double>> x = randomPolygon(rng, 6);
  struct Bound
  {
    double TrajectoryRequest::*field;
    int quantity;  // 0 linear speed, 1 angular speed, 2 linear acceleration, 3 angular acceleration
    double value;
  };
  const std::vector<Bound> bounds{ { &TrajectoryRequest::max_linear_velocity, 0, 0.5 },
                                   { &TrajectoryRequest::max_angular_velocity, 1, 0.3 },
                                   { &TrajectoryRequest::max_linear_acceleration, 2, 0.2 },
                                   { &TrajectoryRequest::max_angular_acceleration, 3, 0.1 } };
  for (const char* curve : { "interpolating", "hermite" })
    for (const Bound& bound : bounds)
    {
      TrajectoryRequest r = requestThrough(x, curve);
      r.geometry = "screw";
      r.*bound.field = bound.value;
      r.sample_count = 20001;
      const TrajectoryResult out = generate(r, test::unhurriedLimits());
      EXPECT_GT(out.time_scale, 1.0);
      double peak = 0.0;
      for (const TrajectorySample& s : out.samples)
      {
        const double q[] = { s.velocity.linear.norm(), s.velocity.angular.norm(), s.acceleration.linear.norm(),
                             s.acceleration.angular.norm() };
        peak = std::max(peak, q[bound.quantity]);
      }
      EXPECT_LE(peak, bound.value * (1.0 + 1e-9)) << curve << " bound " << bound.quantity;
      EXPECT_GE(peak, 0.99 * bound.value) << curve << " bound " << bound.quantity;
    }
}

namespace
{
/// The message `generate` refuses `r` with, "" when it serves it.
std::string refusalOf(const TrajectoryRequest& r)
{
  try
  {
    generate(r, test::unhurriedLimits());
  }
  catch (const InvalidInputError& e)
  {
    return e.what();
  }
  return "";
}
}  // namespace

// A velocity corner (piecewise_geodesic without blend_radius, a B-spline of degree 1) is an impulse
// of acceleration, which no uniform stretch bounds and the figures (peaks of the pieces) do not
// show: under the acceleration bound of a channel whose velocity jumps, `stretch` refuses naming
// that bound, as it refuses an acceleration jump under a jerk bound. A blended corner keeps the
// bound, by differences too; a channel without a bound may still jump.
TEST(Planner, StretchRefusesAVelocityCornerUnderItsAccelerationBound)
{
  std::mt19937 rng(173);
  const std::vector<Pose<double>> x = randomPolygon(rng, 5);
  for (const char* geometry : { "double_geodesic", "screw" })
  {
    TrajectoryRequest r = requestThrough(x, "piecewise_geodesic");
    r.geometry = geometry;
    r.max_linear_acceleration = 1.0;
    std::string why = refusalOf(r);
    EXPECT_EQ(why.rfind("max_linear_acceleration: the curve's velocity jumps at t = ", 0), 0u) << geometry << ": " << why;
    EXPECT_NE(why.find("blend_radius"), std::string::npos) << why;
    EXPECT_NE(why.find("time_optimal"), std::string::npos) << why;
    r.max_linear_acceleration = 0.0;
    r.max_angular_acceleration = 2.0;
    why = refusalOf(r);
    EXPECT_EQ(why.rfind("max_angular_acceleration: ", 0), 0u) << geometry << ": " << why;
    r.curve = "bspline";
    r.degree = 1;
    why = refusalOf(r);
    EXPECT_EQ(why.rfind("max_angular_acceleration: ", 0), 0u) << geometry << ": " << why;

    // Blended corners: served, the bound kept by second differences of the poses at 1 ms.
    r.curve = "piecewise_geodesic";
    r.degree = 0;
    r.blend_radius = 0.2;
    r.max_linear_acceleration = 1.0;
    r.max_angular_acceleration = 0.0;
    r.sample_period = 1e-3;
    const TrajectoryResult out = generate(r, test::unhurriedLimits());
    EXPECT_GT(out.figures.max_linear_acceleration, 0.99);
    EXPECT_LE(out.figures.max_linear_acceleration, 1.0 + 1e-9);
    double worst = 0.0;
    for (std::size_t i = 1; i + 1 < out.samples.size(); ++i)
    {
      const double h = out.samples[i + 1].time - out.samples[i].time;
      if (std::abs(out.samples[i].time - out.samples[i - 1].time - h) > 1e-9)
        continue;  // (the last interval is shorter)
      worst = std::max(worst, (out.samples[i + 1].pose.p - 2.0 * out.samples[i].pose.p + out.samples[i - 1].pose.p).norm() / (h * h));
    }
    EXPECT_LE(worst, 1.0 * (1.0 + 1e-3)) << geometry;
  }
  // A straight translation at one speed turning at the corner: only the angular velocity jumps,
  // and only the linear acceleration is bounded.
  TrajectoryRequest turn;
  turn.curve = "piecewise_geodesic";
  turn.waypoints = { Pose<double>(Quaternion<double>::Identity(), Eigen::Vector3d(0, 0, 0)),
                     Pose<double>(Quaternion<double>(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ())),
                                  Eigen::Vector3d(1, 0, 0)),
                     Pose<double>(Quaternion<double>(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ())),
                                  Eigen::Vector3d(2, 0, 0)) };
  turn.times = { 0.0, 1.0, 2.0 };
  turn.max_linear_acceleration = 1.0;
  EXPECT_EQ(refusalOf(turn), "");
  turn.max_angular_acceleration = 1.0;
  EXPECT_EQ(refusalOf(turn).rfind("max_angular_acceleration: the curve's velocity jumps at t = 1 s", 0), 0u)
      << refusalOf(turn);
}

TEST(Planner, WaypointTimesFollowTheParameterisation)
{
  // Segment distances sqrt(|Δp|² + (ρ Δθ)²) with ρ = 2: 5 (translation 3-4-5), 2 · 1.2 = 2.4
  // (rotation only), sqrt(1.2² + (2 · 0.5)²) = sqrt(2.44).
  TrajectoryRequest r;
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  r.waypoints = { Pose<double>(),
                  Pose<double>(Quaternion<double>::Identity(), Eigen::Vector3d(3, 4, 0)),
                  Pose<double>(so3Exp<double>(Eigen::Vector3d(1.2 * z)), Eigen::Vector3d(3, 4, 0)),
                  Pose<double>(so3Exp<double>(Eigen::Vector3d(1.7 * z)), Eigen::Vector3d(3, 4, 1.2)) };
  r.rotation_scale = 2.0;
  const std::vector<double> d{ 5.0, 2.4, std::sqrt(2.44) };
  auto expected = [&](double (*step)(double), double total) {
    std::vector<double> c{ 0.0 };
    for (double di : d)
      c.push_back(c.back() + step(di));
    for (double& ci : c)
      ci *= total / c.back();
    return c;
  };
  auto check = [&](const std::string& parameterization, double duration, const std::vector<double>& ref) {
    r.parameterization = parameterization;
    r.duration = duration;
    const std::vector<double> times = waypointTimes(validateRequest(r, PlannerLimits()));
    ASSERT_EQ(times.size(), ref.size());
    for (std::size_t i = 0; i < ref.size(); ++i)
      EXPECT_NEAR(times[i], ref[i], 1e-12) << parameterization << " " << i;
  };
  check("", 0.0, expected([](double x) { return x; }, 3.0));  // chord is the default; 1 s per segment
  check("chord", 7.0, expected([](double x) { return x; }, 7.0));
  check("uniform", 0.0, { 0.0, 1.0, 2.0, 3.0 });
  check("uniform", 4.5, { 0.0, 1.5, 3.0, 4.5 });
  check("centripetal", 2.0, expected([](double x) { return std::sqrt(x); }, 2.0));
  // rotation_scale 0 means the default 1 m/rad: the second segment becomes 1.2.
  r.rotation_scale = 0.0;
  r.parameterization = "chord";
  r.duration = 0.0;
  const std::vector<double> times = waypointTimes(validateRequest(r, PlannerLimits()));
  const double total = 5.0 + 1.2 + std::sqrt(1.44 + 0.25);
  EXPECT_NEAR(times[1], 3.0 * 5.0 / total, 1e-12);
  EXPECT_NEAR(times[2], 3.0 * 6.2 / total, 1e-12);
}

TEST(Planner, RequestErrorsNameTheField)
{
  std::mt19937 rng(173);
  const std::vector<Pose<double>> x = randomPolygon(rng, 4);
  auto message = [&](TrajectoryRequest r) {
    try
    {
      generate(r, test::unhurriedLimits());
    }
    catch (const InterpolationError& e)
    {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  TrajectoryRequest r = requestThrough(x, "hermite");
  r.velocities.resize(3);
  EXPECT_NE(message(r).find("velocities: 3 given for 4 waypoints"), std::string::npos) << message(r);
  r.velocities.resize(4);
  r.velocities[2].angular.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message(r).find("velocities[2].angular.y"), std::string::npos) << message(r);
  r.velocities[2].angular = Eigen::Vector3d(0.0, 0.0, 1e3);  // far too fast for its segment
  EXPECT_NE(message(r).find("velocities[2]: too large"), std::string::npos) << message(r);
  r = requestThrough(x, "interpolating");
  r.end_condition = "free";
  EXPECT_NE(message(r).find("end_condition: unknown value 'free'"), std::string::npos) << message(r);
  r.end_condition = "clamped";
  r.start_velocity.linear.x() = std::numeric_limits<double>::infinity();
  EXPECT_NE(message(r).find("start_velocity.linear.x"), std::string::npos) << message(r);
}
