// curve fit through the request (planner/families/fit.h): the served curve is the fit's B-spline
// (its control poses and knots in the result replay it as a `bspline` request to 1e-12), every
// timing applies to it (stretch within the bounds, time_optimal with jerk bounds from rest to
// rest), the start state joins it, and each of its fields is refused where it is wrong, naming it.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "se3_interpolation/fitting/bspline_fit.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/planner/validation.h"

using namespace se3_interpolation;

namespace
{
/// 4 s of a slow motion sampled at 50 Hz with 1 mm and 0.5° of noise.
TrajectoryRequest recording(unsigned seed = 3)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  TrajectoryRequest r;
  for (int i = 0; i <= 200; ++i)
  {
    const double t = i * 0.02;
    Pose<double> x(so3Exp(Eigen::Vector3d(0.4 * std::sin(0.5 * t), 0.2 * t, 0.1)),
                   Eigen::Vector3d(0.3 * std::sin(0.6 * t), 0.1 * t, 0.05 * std::cos(0.4 * t)));
    x.p += 0.001 * Eigen::Vector3d(n(rng), n(rng), n(rng));
    x.q = x.q * so3Exp(Eigen::Vector3d(0.0087 * Eigen::Vector3d(n(rng), n(rng), n(rng))));
    if (i % 5 == 0)
      x.q.coeffs() = -x.q.coeffs();
    r.waypoints.push_back(x);
    r.times.push_back(t);
  }
  r.curve = "fit";
  r.control_period = 0.5;
  return r;
}

std::string errorOf(const TrajectoryRequest& r)
{
  try
  {
    generate(r, PlannerLimits());
  }
  catch (const std::invalid_argument& e)
  {
    return e.what();
  }
  return "";
}

bool startsWith(const std::string& s, const std::string& prefix)
{
  return s.compare(0, prefix.size(), prefix) == 0;
}
}  // namespace

TEST(FitRequest, ServesTheFittedBSplineAndReportsIt)
{
  for (const char* geometry : { "double_geodesic", "screw" })
  {
    TrajectoryRequest r = recording();
    r.geometry = geometry;
    r.sample_count = 57;
    const TrajectoryResult fit = generate(r, PlannerLimits());
    // The fit itself, called directly.
    FitOptions o;
    o.control_period = 0.5;
    std::vector<Pose<double>> poses = r.waypoints;
    const BSplineFitResult direct = std::string(geometry) == "screw" ? fitBSpline<ScrewSe3>(poses, r.times, o)
                                                                     : fitBSpline<DoubleGeodesicSe3>(poses, r.times, o);
    ASSERT_EQ(fit.control_points.size(), direct.control.size());
    EXPECT_EQ(fit.knots, direct.knots);
    EXPECT_EQ(fit.control_points.size(), 8u + 3u);  // ⌈4 / 0.5⌉ intervals + degree 3
    EXPECT_NEAR(fit.residual_linear, direct.residual_linear, 1e-12);  // the request normalises quaternions
    EXPECT_NEAR(fit.residual_angular, direct.residual_angular, 1e-12);
    EXPECT_GT(fit.residual_linear, 0.0005);
    EXPECT_LT(fit.residual_linear, 0.003);
    EXPECT_GT(fit.residual_angular, 0.005);
    EXPECT_LT(fit.residual_angular, 0.03);
    // The replay: a bspline request of the control poses and knots gives the same samples.
    TrajectoryRequest replay;
    replay.curve = "bspline";
    replay.geometry = geometry;
    replay.waypoints = fit.control_points;
    replay.knots = fit.knots;
    replay.degree = 3;
    replay.sample_count = 57;
    const TrajectoryResult again = generate(replay, PlannerLimits());
    ASSERT_EQ(again.samples.size(), fit.samples.size());
    for (std::size_t i = 0; i < fit.samples.size(); ++i)
    {
      EXPECT_NEAR(again.samples[i].time, fit.samples[i].time, 1e-12);
      EXPECT_LT((again.samples[i].pose.p - fit.samples[i].pose.p).norm(), 1e-12) << i;
      EXPECT_LT((again.samples[i].pose.q.coeffs() - fit.samples[i].pose.q.coeffs()).norm(), 1e-12) << i;
      EXPECT_LT((again.samples[i].velocity.linear - fit.samples[i].velocity.linear).norm(), 1e-10) << i;
    }
    // The curve spans the recording's times.
    EXPECT_DOUBLE_EQ(fit.start_time, 0.0);
    EXPECT_NEAR(fit.duration, 4.0, 1e-12);
  }
}

TEST(FitRequest, EveryTimingAppliesToTheFit)
{
  TrajectoryRequest r = recording();
  r.max_linear_velocity = 0.05;
  r.max_angular_velocity = 0.1;
  r.sample_period = 0.01;
  const TrajectoryResult stretched = generate(r, PlannerLimits());
  EXPECT_GT(stretched.time_scale, 1.0);
  EXPECT_LE(stretched.figures.max_linear_speed, 0.05 * (1 + 1e-9));
  EXPECT_LE(stretched.figures.max_angular_speed, 0.1 * (1 + 1e-9));
  r.timing = "time_optimal";
  r.max_linear_acceleration = 0.2;
  r.max_angular_acceleration = 0.4;
  r.max_linear_jerk = 1.0;
  r.max_angular_jerk = 2.0;
  const TrajectoryResult optimal = generate(r, PlannerLimits());
  EXPECT_LE(optimal.figures.max_linear_speed, 0.05 * (1 + 1e-9));
  EXPECT_LE(optimal.figures.max_linear_acceleration, 0.2 * (1 + 1e-9));
  EXPECT_LE(optimal.figures.max_linear_jerk, 1.0 * (1 + 1e-6));
  EXPECT_LT(optimal.samples.back().velocity.linear.norm(), 1e-9);
  EXPECT_LT(optimal.samples.front().velocity.linear.norm(), 1e-9);
  EXPECT_GT(optimal.residual_linear, 0.0);  // reported whatever the timing
}

TEST(FitRequest, RefusesEachFieldNamingIt)
{
  TrajectoryRequest r = recording();
  r.times.clear();
  EXPECT_TRUE(startsWith(errorOf(r), "times: curve 'fit' needs the waypoints' times")) << errorOf(r);
  r = recording();
  r.control_period = -0.1;
  EXPECT_TRUE(startsWith(errorOf(r), "control_period:")) << errorOf(r);
  r.control_period = 1e-9;
  EXPECT_TRUE(startsWith(errorOf(r), "control_period:")) << errorOf(r);
  r = recording();
  r.smoothing = -1.0;
  EXPECT_TRUE(startsWith(errorOf(r), "smoothing:")) << errorOf(r);
  r.smoothing = std::nan("");
  EXPECT_TRUE(startsWith(errorOf(r), "smoothing:")) << errorOf(r);
  r = recording();
  r.loss = "cauchy";
  EXPECT_TRUE(startsWith(errorOf(r), "loss:")) << errorOf(r);
  r.loss = "huber";
  EXPECT_TRUE(startsWith(errorOf(r), "loss_scale:")) << errorOf(r);
  r.loss_scale = 0.01;
  EXPECT_EQ(errorOf(r), "");
  r = recording();
  r.degree = 6;
  EXPECT_TRUE(startsWith(errorOf(r), "degree:")) << errorOf(r);
  // The fit's fields are refused for every other family.
  for (const char* curve : { "interpolating", "bspline", "piecewise_geodesic" })
  {
    TrajectoryRequest other = recording();
    other.waypoints.resize(5);
    other.times.resize(5);
    other.curve = curve;
    other.control_period = 0.0;
    other.smoothing = 1.0;
    EXPECT_EQ(errorOf(other), std::string("smoothing: only used by curve 'fit' (curve is '") + curve + "')");
    other.smoothing = 0.0;
    other.loss = "huber";
    EXPECT_TRUE(startsWith(errorOf(other), "loss: only used by curve 'fit'")) << errorOf(other);
  }
  // A gap in the recording (no pose from 1.0 s to 2.2 s) with a fine control period.
  r = recording();
  TrajectoryRequest gap = r;
  gap.waypoints.clear();
  gap.times.clear();
  for (std::size_t i = 0; i < r.times.size(); ++i)
    if (r.times[i] < 1.0 || r.times[i] > 2.2)
    {
      gap.waypoints.push_back(r.waypoints[i]);
      gap.times.push_back(r.times[i]);
    }
  gap.control_period = 0.2;
  EXPECT_TRUE(startsWith(errorOf(gap), "control_period: the waypoints leave control pose")) << errorOf(gap);
  gap.smoothing = 1e-6;
  EXPECT_EQ(errorOf(gap), "");
  // The sphere has no fit.
  SphereRequest s;
  s.waypoints = { Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1) };
  s.times = { 0, 1, 2 };
  s.curve = "fit";
  try
  {
    generate(s, PlannerLimits());
    ADD_FAILURE() << "the sphere fitted";
  }
  catch (const InvalidInputError& e)
  {
    EXPECT_TRUE(startsWith(e.what(), "curve: 'fit' fits poses")) << e.what();
  }
}

TEST(FitRequest, AMovingStartJoinsTheFit)
{
  TrajectoryRequest r = recording();
  StartState s;
  s.pose = Pose<double>(Quaternion<double>::Identity(), Eigen::Vector3d(-0.05, 0.0, 0.0));
  s.velocity.linear = Eigen::Vector3d(0.02, 0.0, 0.0);
  r.start_state = s;
  for (double& t : r.times)
    t += 0.5;
  r.sample_period = 0.01;
  const TrajectoryResult out = generate(r, PlannerLimits());
  EXPECT_LT((out.samples.front().pose.p - s.pose.p).norm(), 1e-9);
  EXPECT_LT((out.samples.front().velocity.linear - s.velocity.linear).norm(), 1e-9);
}

TEST(FitRequest, AStartAtRestJoinsTheFitAndReportsTheFittedControlPoses)
{
  // The fit passes near the start pose (its first fitted point, at time 0), not through it: the
  // motion starts at the start pose itself (the joining segment, at rest there), and control_points
  // are the fitted B-spline's (as many as its knots take), not the joined motion's with the start
  // pose in front.
  TrajectoryRequest r = recording();
  StartState s;
  s.pose = Pose<double>(so3Exp(Eigen::Vector3d(0.0, 0.0, 0.2)), Eigen::Vector3d(-0.05, 0.02, 0.0));
  r.start_state = s;
  for (double& t : r.times)
    t += 0.5;
  r.max_linear_acceleration = 0.5;
  r.max_angular_acceleration = 1.0;
  r.sample_count = 50;
  for (const char* timing : { "stretch", "time_optimal" })
  {
    r.timing = timing;
    const TrajectoryResult out = generate(r, PlannerLimits());
    EXPECT_LT((out.samples.front().pose.p - s.pose.p).norm(), 1e-9) << timing;
    EXPECT_LT(out.samples.front().pose.q.angularDistance(s.pose.q), 1e-9) << timing;
    EXPECT_LT(out.samples.front().velocity.linear.norm(), 1e-9) << timing;
    EXPECT_EQ(out.control_points.size() + 3u + 1u, out.knots.size()) << timing;
    EXPECT_EQ(out.knots.front(), 0.0) << timing;
  }
  // constant_speed from rest: the joining segment stands still at its start, where no path speed
  // holds a chord speed; refused naming speed (it was served starting away from the start pose).
  r.timing = "constant_speed";
  r.speed = 0.05;
  EXPECT_TRUE(startsWith(errorOf(r), "speed: the path stands still at path time 0 s")) << errorOf(r);
}
