// Time-optimal timing (timing/time_optimal.h, request field `timing: time_optimal`). Every
// figure is checked against something computed independently here: the closed-form trapezoid /
// triangle profiles of straight lines and single-axis rotations, sums of per-segment trapezoids on
// polylines, and on curved paths a brute-force reference (dense grid, bisection for the admissible
// accelerations, forward and backward integration) that uses the vector norms |C″ x + C′ u| directly.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <string>

#include "se3_interpolation/planner/curve_factory.h"
#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "se3_interpolation/planner/validation.h"
#include "test_utils.h"

using namespace se3_interpolation;

namespace
{
// ---- Independent references ------------------------------------------------------------

/// Rest-to-rest time over distance d with speed ≤ v and |acceleration| ≤ a (v = 0: unbounded):
/// the trapezoid d/v + v/a, or the triangle 2√(d/a) when the cruise speed is not reached.
double trapezoidTime(double d, double v, double a)
{
  if (v > 0.0 && v * v / a < d)
    return d / v + v / a;
  return 2.0 * std::sqrt(d / a);
}

struct Bounds4
{
  double v = 0.0, w = 0.0, a = 0.0, alpha = 0.0;
};

/// The brute-force reference: on a dense uniform grid of the path parameter, the largest
/// admissible x = ṡ² at each point (max velocity curve), a backward integration at the strongest
/// admissible deceleration from rest at the end and a forward integration at the strongest
/// admissible acceleration from rest at the start, each clipped by the other and by the max
/// velocity curve. The admissible accelerations u for a given x are found by bisection on the
/// vector norms |C″ x + C′ u| of each channel (no closed form).
class BruteForce
{
public:
  struct Point
  {
    Eigen::Vector3d b[2], a[2];  // C′, C″ of the linear and angular channel
  };

  BruteForce(std::vector<Point> points, double ds, Bounds4 bounds, std::vector<std::size_t> rest)
    : p_(std::move(points)), ds_(ds), bounds_(bounds), rest_(std::move(rest))
  {
  }

  double duration() const
  {
    const std::size_t n = p_.size();
    std::vector<double> mvc(n);
    for (std::size_t i = 0; i < n; ++i)
      mvc[i] = maxVelocity(i);
    mvc.front() = mvc.back() = 0.0;
    for (std::size_t i : rest_)
      mvc[i] = 0.0;
    // Backward: the largest x_i from which full braking stays below beta_{i+1}.
    std::vector<double> beta(n, 0.0);
    for (std::size_t i = n - 1; i-- > 0;)
    {
      if (mvc[i] == 0.0)
        continue;
      double lo = 0.0, hi = mvc[i];
      auto ok = [&](double x) {
        double umin, umax;
        if (!controls(i, x, &umin, &umax))
          return false;
        return x + 2.0 * ds_ * umin <= beta[i + 1];
      };
      if (ok(hi))
        lo = hi;
      else
        for (int k = 0; k < 60; ++k)
        {
          const double mid = 0.5 * (lo + hi);
          (ok(mid) ? lo : hi) = mid;
        }
      beta[i] = lo;
    }
    // Forward: full acceleration, clipped by the braking curve.
    std::vector<double> x(n, 0.0);
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
      double umin = 0.0, umax = 0.0;
      controls(i, x[i], &umin, &umax);
      x[i + 1] = std::max(0.0, std::min(beta[i + 1], x[i] + 2.0 * ds_ * umax));
    }
    double t = 0.0;
    for (std::size_t i = 0; i + 1 < n; ++i)
      t += 2.0 * ds_ / (std::sqrt(x[i]) + std::sqrt(x[i + 1]));
    return t;
  }

private:
  double accelerationBound(int c) const { return c == 0 ? bounds_.a : bounds_.alpha; }

  /// Largest x with some admissible u (bisection on x, the velocity bounds included).
  double maxVelocity(std::size_t i) const
  {
    double hi = 1e12;
    for (int c = 0; c < 2; ++c)
    {
      const double v = c == 0 ? bounds_.v : bounds_.w;
      const double n = p_[i].b[c].norm();
      if (v > 0.0 && n > 0.0)
        hi = std::min(hi, v * v / (n * n));
    }
    double umin, umax;
    if (controls(i, hi, &umin, &umax))
      return hi;
    double lo = 0.0;
    for (int k = 0; k < 100; ++k)
    {
      const double mid = 0.5 * (lo + hi);
      (controls(i, mid, &umin, &umax) ? lo : hi) = mid;
    }
    return lo;
  }

  /// The worst violation max_c (|a_c x + b_c u| − A_c) at (x, u): convex in u.
  double violation(std::size_t i, double x, double u) const
  {
    double worst = -1e300;
    for (int c = 0; c < 2; ++c)
      if (accelerationBound(c) > 0.0)
        worst = std::max(worst, (p_[i].a[c] * x + p_[i].b[c] * u).norm() - accelerationBound(c));
    return worst;
  }

  /// The admissible u at (i, x): golden-section minimum of the violation, then bisection of both ends.
  bool controls(std::size_t i, double x, double* umin, double* umax) const
  {
    const double span = 1e4;
    double a = -span, b = span;
    const double r = 0.5 * (std::sqrt(5.0) - 1.0);
    double x1 = b - r * (b - a), x2 = a + r * (b - a);
    double f1 = violation(i, x, x1), f2 = violation(i, x, x2);
    for (int k = 0; k < 64; ++k)
    {
      if (f1 < f2)
      {
        b = x2;
        x2 = x1;
        f2 = f1;
        x1 = b - r * (b - a);
        f1 = violation(i, x, x1);
      }
      else
      {
        a = x1;
        x1 = x2;
        f1 = f2;
        x2 = a + r * (b - a);
        f2 = violation(i, x, x2);
      }
    }
    const double best = 0.5 * (a + b);
    if (violation(i, x, best) > 0.0)
      return false;
    double lo = -span, hi = best;
    for (int k = 0; k < 48; ++k)
    {
      const double mid = 0.5 * (lo + hi);
      (violation(i, x, mid) <= 0.0 ? hi : lo) = mid;
    }
    *umin = hi;
    lo = best;
    hi = span;
    for (int k = 0; k < 48; ++k)
    {
      const double mid = 0.5 * (lo + hi);
      (violation(i, x, mid) <= 0.0 ? lo : hi) = mid;
    }
    *umax = lo;
    return true;
  }

  std::vector<Point> p_;
  double ds_;
  Bounds4 bounds_;
  std::vector<std::size_t> rest_;
};

template <class G>
double bruteForceDuration(const Curve<G>& curve, Bounds4 bounds, std::size_t n = 2000)
{
  std::vector<BruteForce::Point> points(n + 1);
  const double s0 = curve.startTime(), s1 = curve.endTime();
  const double ds = (s1 - s0) / static_cast<double>(n);
  for (std::size_t i = 0; i <= n; ++i)
  {
    const Kinematics k = kinematicsAt(curve, s0 + ds * static_cast<double>(i));
    points[i].b[0] = k.velocity.linear;
    points[i].b[1] = k.velocity.angular;
    points[i].a[0] = k.acceleration.linear;
    points[i].a[1] = k.acceleration.angular;
  }
  return BruteForce(points, ds, bounds, {}).duration();
}

TrajectoryRequest timeOptimalRequest(std::vector<Pose<double>> waypoints, Bounds4 b)
{
  TrajectoryRequest r;
  r.waypoints = std::move(waypoints);
  r.timing = "time_optimal";
  r.max_linear_velocity = b.v;
  r.max_angular_velocity = b.w;
  r.max_linear_acceleration = b.a;
  r.max_angular_acceleration = b.alpha;
  return r;
}

Pose<double> pose(double angle_z, const Eigen::Vector3d& p)
{
  return Pose<double>(so3Exp<double>(Eigen::Vector3d(0, 0, angle_z)), p);
}

std::string errorOf(const TrajectoryRequest& r)
{
  try
  {
    generate(r, test::unhurriedLimits());
  }
  catch (const InvalidInputError& e)
  {
    return e.what();
  }
  return "no error";
}

/// No sample above its bound (relative 1e-9), at rest at both ends.
void expectWithinBounds(const TrajectoryResult& out, Bounds4 b, const std::string& what)
{
  for (const TrajectorySample& s : out.samples)
  {
    // An unbounded rate (0) is checked against +inf.
    auto bound = [](double x) { return x > 0.0 ? x * (1.0 + 1e-9) : std::numeric_limits<double>::infinity(); };
    ASSERT_LE(s.velocity.linear.norm(), bound(b.v)) << what << " t = " << s.time;
    ASSERT_LE(s.velocity.angular.norm(), bound(b.w)) << what << " t = " << s.time;
    ASSERT_LE(s.acceleration.linear.norm(), bound(b.a)) << what << " t = " << s.time;
    ASSERT_LE(s.acceleration.angular.norm(), bound(b.alpha)) << what << " t = " << s.time;
  }
  EXPECT_EQ(out.samples.front().velocity.linear.norm(), 0.0) << what;
  EXPECT_EQ(out.samples.front().velocity.angular.norm(), 0.0) << what;
  EXPECT_EQ(out.samples.back().velocity.linear.norm(), 0.0) << what;
  EXPECT_EQ(out.samples.back().velocity.angular.norm(), 0.0) << what;
}
}  // namespace

// ---- Closed forms ----------------------------------------------------------------------

TEST(TimeOptimal, StraightLineIsTheTrapezoidOrTheTriangle)
{
  const std::vector<Pose<double>> line{ pose(0.0, Eigen::Vector3d(1, 2, 3)), pose(0.0, Eigen::Vector3d(2.2, 0.4, 3)) };
  const double d = (line[1].p - line[0].p).norm();
  for (const char* geometry : { "double_geodesic", "screw" })
    for (Bounds4 b : { Bounds4{ 0.5, 0, 1.0, 0 }, Bounds4{ 10.0, 0, 1.0, 0 }, Bounds4{ 0, 0, 3.0, 0 },
                       Bounds4{ 0.3, 1.0, 2.0, 5.0 } })
    {
      TrajectoryRequest r = timeOptimalRequest(line, b);
      r.geometry = geometry;
      r.sample_count = 10000;
      const TrajectoryResult out = generate(r, test::unhurriedLimits());
      const double expected = trapezoidTime(d, b.v, b.a);
      EXPECT_NEAR(out.duration, expected, 0.005 * expected) << geometry << " v " << b.v << " a " << b.a;
      EXPECT_GE(out.duration, expected * (1.0 - 1e-9)) << "faster than the optimum";
      expectWithinBounds(out, b, geometry);
      EXPECT_NEAR(out.figures.length, d, 1e-9);
    }
}

TEST(TimeOptimal, PureRotationIsTheTrapezoidOrTheTriangle)
{
  const Eigen::Vector3d p(0.5, -1, 2);
  const std::vector<Pose<double>> turn{ pose(0.3, p), pose(2.8, p) };
  for (const char* geometry : { "double_geodesic", "screw" })
    for (Bounds4 b : { Bounds4{ 0, 0.8, 0, 2.0 }, Bounds4{ 0, 8.0, 0, 2.0 }, Bounds4{ 1.0, 0.5, 1.0, 0.7 } })
    {
      TrajectoryRequest r = timeOptimalRequest(turn, b);
      r.geometry = geometry;
      r.sample_count = 10000;
      const TrajectoryResult out = generate(r, test::unhurriedLimits());
      const double expected = trapezoidTime(2.5, b.w, b.alpha);
      EXPECT_NEAR(out.duration, expected, 0.005 * expected) << geometry << " w " << b.w;
      EXPECT_GE(out.duration, expected * (1.0 - 1e-9));
      expectWithinBounds(out, b, geometry);
    }
}

TEST(TimeOptimal, DoubleGeodesicPolylineIsTheSumOfItsSegmentTrapezoids)
{
  // Each segment moves λ ∈ [0, 1] with p = p_i + λ d_i and a rotation λ θ_i about one axis, so
  // |ṗ| = |d| λ̇, |ω| = θ λ̇ (and the same for the accelerations): a trapezoid in λ with the
  // tightest speed and acceleration limits of the two channels; the motion stops at each corner.
  const std::vector<Pose<double>> w{ pose(0.0, Eigen::Vector3d(0, 0, 0)), pose(1.0, Eigen::Vector3d(1, 0, 0)),
                                     pose(1.2, Eigen::Vector3d(1, 2, 0)), pose(-0.5, Eigen::Vector3d(1, 2, 0.3)) };
  const Bounds4 b{ 0.6, 0.9, 1.5, 2.0 };
  TrajectoryRequest r = timeOptimalRequest(w, b);
  r.curve = "piecewise_geodesic";
  r.times = { 0.0, 1.0, 1.5, 4.0 };  // very uneven path times: the timing must not depend on them
  r.sample_count = 10000;
  const TrajectoryResult out = generate(r, test::unhurriedLimits());
  double expected = 0.0;
  std::vector<double> corner_times{ 0.0 };
  for (std::size_t i = 0; i + 1 < w.size(); ++i)
  {
    const double d = (w[i + 1].p - w[i].p).norm();
    const double theta = rotationAngle(Quaternion<double>(w[i].q.conjugate() * w[i + 1].q));
    const double vmax = std::min(b.v / d, b.w / theta);
    const double amax = std::min(b.a / d, b.alpha / theta);
    expected += trapezoidTime(1.0, vmax, amax);
    corner_times.push_back(expected);
  }
  EXPECT_NEAR(out.duration, expected, 0.005 * expected);
  expectWithinBounds(out, b, "polyline");
  // The reported waypoint times are those of the timed motion: the corners, where it rests.
  ASSERT_EQ(out.waypoint_times.size(), w.size());
  for (std::size_t i = 0; i < w.size(); ++i)
  {
    EXPECT_NEAR(out.waypoint_times[i], corner_times[i], 0.005 * expected) << i;
    EXPECT_LT(test::poseDistance(out.point_at(out.waypoint_times[i]), w[i]), 1e-9) << i;
  }
  for (const TrajectorySample& s : out.samples)
    for (std::size_t i = 1; i + 1 < w.size(); ++i)
      if (s.time == out.waypoint_times[i])
      {
        EXPECT_EQ(s.velocity.linear.norm(), 0.0);
      }
}

TEST(TimeOptimal, RestsAtABSplineKnotOfFullMultiplicityOnly)
{
  // Quadratic B-spline: the knot 1 has multiplicity 2 = degree (C⁰: a velocity corner through the
  // control point), the knot 0.5 multiplicity 1 (C¹: no corner).
  std::mt19937 rng(17);
  const std::vector<Pose<double>> control = test::randomPolygon(rng, 6, 0.6);
  auto curve = std::make_shared<BSplineCurve<ScrewSe3>>(control, 2,
                                                         std::vector<double>{ 0, 0, 0, 0.5, 1, 1, 2, 2, 2 });
  ASSERT_GT((kinematicsAt(*curve, 1.0, Side::kLeft).velocity.linear -
             kinematicsAt(*curve, 1.0, Side::kRight).velocity.linear).norm(), 0.1);
  timing::RateBounds bounds;
  bounds.velocity = { 1.0, 1.0 };
  bounds.acceleration = { 2.0, 2.0 };
  const auto timed = timing::makeTimeOptimalCurve<ScrewSe3>(curve, bounds);
  const timing::TimingProfile& p = timed->profile();
  auto at = [&](double s) {
    const auto it = std::find(p.s.begin(), p.s.end(), s);
    EXPECT_NE(it, p.s.end()) << s << " is not a grid point";
    return static_cast<std::size_t>(it - p.s.begin());
  };
  EXPECT_EQ(p.x[at(1.0)], 0.0);
  EXPECT_GT(p.x[at(0.5)], 0.0);
  const double t_corner = p.timeAt(1.0);
  EXPECT_EQ(kinematicsAt(*timed, t_corner, Side::kLeft).velocity.linear.norm(), 0.0);
  EXPECT_EQ(kinematicsAt(*timed, t_corner, Side::kRight).velocity.linear.norm(), 0.0);
  EXPECT_LT(test::poseDistance(timed->value(t_corner), control[3]), 1e-12);
}

TEST(TimeOptimal, GreatCircleArcOnTheSphereIsTheTrapezoid)
{
  SphereRequest r;
  r.waypoints = { Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(std::cos(2.0), std::sin(2.0), 0) };
  r.timing = "time_optimal";
  r.max_angular_velocity = 0.7;
  r.max_angular_acceleration = 1.1;
  r.sample_count = 10000;
  const SphereResult out = generate(r, test::unhurriedLimits());
  const double expected = trapezoidTime(2.0, 0.7, 1.1);
  EXPECT_NEAR(out.duration, expected, 0.005 * expected);
  for (const SphereSample& s : out.samples)
  {
    ASSERT_LE(s.velocity.norm(), 0.7 * (1 + 1e-9));
    ASSERT_LE(s.acceleration.norm(), 1.1 * (1 + 1e-9));
  }
  EXPECT_EQ(out.samples.front().velocity.norm(), 0.0);
  EXPECT_EQ(out.samples.back().velocity.norm(), 0.0);
}

// ---- Curved paths against the brute-force reference -------------------------------------

TEST(TimeOptimal, TheBruteForceReferenceGivesTheTrapezoidOnAStraightLine)
{
  // The reference itself, against the closed form (cruise reached, and not).
  const PiecewiseGeodesic<DoubleGeodesicSe3> line(
      { pose(0.0, Eigen::Vector3d(0, 0, 0)), pose(0.0, Eigen::Vector3d(0, 1.5, 2)) }, { 0.0, 1.0 });
  EXPECT_NEAR(bruteForceDuration(line, Bounds4{ 0.5, 0, 1.0, 0 }) / trapezoidTime(2.5, 0.5, 1.0), 1.0, 2e-3);
  EXPECT_NEAR(bruteForceDuration(line, Bounds4{ 5.0, 0, 1.0, 0 }) / trapezoidTime(2.5, 5.0, 1.0), 1.0, 2e-3);
  const PiecewiseGeodesic<DoubleGeodesicSe3> turn(
      { pose(0.0, Eigen::Vector3d(0, 0, 0)), pose(2.0, Eigen::Vector3d(0, 0, 0)) }, { 0.0, 1.0 });
  EXPECT_NEAR(bruteForceDuration(turn, Bounds4{ 0, 0.7, 0, 1.3 }) / trapezoidTime(2.0, 0.7, 1.3), 1.0, 2e-3);
}

TEST(TimeOptimal, EveryCurveFamilyAndGeometryMatchesTheBruteForceReference)
{
  std::mt19937 rng(13);
  const std::vector<Pose<double>> w = test::randomPolygon(rng, 5, 0.9);
  const Bounds4 b{ 0.8, 1.2, 1.5, 2.5 };
  for (const char* geometry : { "double_geodesic", "screw" })
    for (const char* curve : { "bezier", "bspline", "interpolating", "hermite", "blended" })
    {
      TrajectoryRequest r = timeOptimalRequest(w, b);
      r.curve = curve;
      r.geometry = geometry;
      r.sample_count = 10000;
      const TrajectoryResult out = generate(r, test::unhurriedLimits());
      const ValidatedRequest v = validateRequest(r, PlannerLimits());
      const std::vector<double> times = waypointTimes(v);
      double reference = 0.0;
      if (v.geometry == GeometryType::kScrew)
        reference = bruteForceDuration(*makeCurve<ScrewSe3>(v, times), b);
      else
        reference = bruteForceDuration(*makeCurve<DoubleGeodesicSe3>(v, times), b);
      EXPECT_NEAR(out.duration / reference, 1.0, 0.01) << curve << " " << geometry;
      expectWithinBounds(out, b, std::string(curve) + " " + geometry);
      if (std::string(curve) != "bezier" && std::string(curve) != "bspline")
      {
        for (std::size_t i = 0; i < w.size(); ++i)
          EXPECT_LT(test::poseDistance(out.point_at(out.waypoint_times[i]), w[i]), 1e-9) << curve << " " << i;
      }
    }
}

TEST(TimeOptimal, ReportedVelocitiesAreTheFiniteDifferencesOfThePoses)
{
  std::mt19937 rng(7);
  const std::vector<Pose<double>> w = test::randomPolygon(rng, 4, 0.8);
  TrajectoryRequest r = timeOptimalRequest(w, Bounds4{ 1.0, 1.0, 2.0, 3.0 });
  r.curve = "interpolating";
  r.geometry = "screw";
  r.sample_count = 50;
  const TrajectoryResult out = generate(r, test::unhurriedLimits());
  // s̈ is constant per grid interval, so the acceleration jumps at grid points and a stencil that
  // spans one errs by about |Δa| h: h small enough for that (and the h⁴ terms) to stay below 1e-7,
  // large enough for rounding (1e-16 |p| / h) to stay below 1e-10.
  const double h = 1e-5 * out.duration;
  for (std::size_t i = 1; i + 1 < out.samples.size(); ++i)
  {
    const TrajectorySample& s = out.samples[i];
    const Kinematics fd = test::centralDifferences(out.point_at, s.time, h);
    EXPECT_LT((fd.velocity.linear - s.velocity.linear).norm(), 1e-6) << s.time;
    EXPECT_LT((fd.velocity.angular - s.velocity.angular).norm(), 1e-6) << s.time;
  }
}

TEST(TimeOptimal, AccelerationsAreTheDerivativesOfTheVelocities)
{
  // Inside one interval of the profile s̈ is constant, so a = dv/dt there (away from the jumps).
  std::mt19937 rng(11);
  const std::vector<Pose<double>> w = test::randomPolygon(rng, 4, 0.8);
  auto path = makeCurve<ScrewSe3>(validateRequest(timeOptimalRequest(w, Bounds4{}), PlannerLimits()),
                                  { 0.0, 1.0, 2.5, 3.0 });
  timing::RateBounds bounds;
  bounds.velocity = { 1.0, 1.0 };
  bounds.acceleration = { 2.0, 3.0 };
  const auto timed = timing::makeTimeOptimalCurve<ScrewSe3>(path, bounds);
  const timing::TimingProfile& p = timed->profile();
  for (std::size_t i = 1; i + 1 < p.t.size(); i += 37)
  {
    const double t = 0.5 * (p.t[i] + p.t[i + 1]);
    const double h = 1e-3 * (p.t[i + 1] - p.t[i]);
    const Kinematics k = kinematicsAt(*timed, t);
    const Kinematics plus = kinematicsAt(*timed, t + h), minus = kinematicsAt(*timed, t - h);
    const double scale = 1.0 + k.acceleration.linear.norm() + k.acceleration.angular.norm();
    EXPECT_LT(((plus.velocity.linear - minus.velocity.linear) / (2 * h) - k.acceleration.linear).norm(), 1e-5 * scale);
    EXPECT_LT(((plus.velocity.angular - minus.velocity.angular) / (2 * h) - k.acceleration.angular).norm(),
              1e-5 * scale);
    // And the timed pose is the path's pose at s(t).
    EXPECT_LT(test::poseDistance(timed->value(t), path->value(p.pathParameter(t, Side::kRight))), 1e-15);
  }
  // s⁻¹ inverts s.
  for (double s : { 0.1, 1.0, 1.7, 2.9 })
    EXPECT_NEAR(p.pathParameter(p.timeAt(s), Side::kRight), s, 1e-12) << s;
}

TEST(TimeOptimal, ReportedFiguresAreThoseOfTheTimedMotion)
{
  // The response's peaks and energy (from the timing's own checks) against measureCurve's
  // Gauss–Legendre integration and golden-section peaks on the timed curve; the lengths against
  // the untimed path's (a reparameterisation keeps them).
  std::mt19937 rng(5);
  const std::vector<Pose<double>> w = test::randomPolygon(rng, 4, 0.8);
  for (const Bounds4 b : { Bounds4{ 0.7, 0.9, 1.2, 2.0 }, Bounds4{ 0.0, 0.0, 1.2, 0.0 } })
  {
    TrajectoryRequest r = timeOptimalRequest(w, b);
    r.curve = "hermite";
    r.rotation_scale = 0.5;
    const TrajectoryResult out = generate(r, test::unhurriedLimits());
    const ValidatedRequest v = validateRequest(r, PlannerLimits());
    const auto path = makeCurve<DoubleGeodesicSe3>(v, waypointTimes(v));
    timing::RateBounds bounds;
    bounds.velocity = { b.v, b.w };
    bounds.acceleration = { b.a, b.alpha };
    const auto timed = timing::makeTimeOptimalCurve<DoubleGeodesicSe3>(path, bounds);
    const CurveFigures timed_fig = measureCurve(*timed, 0.5);
    const CurveFigures path_fig = measureCurve(*path, 0.5);
    EXPECT_NEAR(out.duration, timed->endTime() - timed->startTime(), 1e-12);
    EXPECT_NEAR(out.figures.length, path_fig.length, 1e-12);
    EXPECT_NEAR(out.figures.length, timed_fig.length, 1e-6 * out.figures.length);
    EXPECT_NEAR(out.figures.rotation_length, timed_fig.rotation_length, 1e-6 * out.figures.rotation_length);
    EXPECT_NEAR(out.figures.energy, timed_fig.energy, 2e-3 * timed_fig.energy);
    EXPECT_NEAR(out.figures.max_linear_speed, timed_fig.max_linear_speed, 1e-6 * timed_fig.max_linear_speed);
    EXPECT_NEAR(out.figures.max_angular_speed, timed_fig.max_angular_speed, 1e-3 * timed_fig.max_angular_speed);
    EXPECT_NEAR(out.figures.max_linear_acceleration, timed_fig.max_linear_acceleration,
                1e-3 * timed_fig.max_linear_acceleration);
    EXPECT_NEAR(out.figures.max_angular_acceleration, timed_fig.max_angular_acceleration,
                1e-3 * timed_fig.max_angular_acceleration);
  }
}

TEST(TimeOptimal, FasterThanTheUniformStretch)
{
  std::mt19937 rng(3);
  TrajectoryRequest r = timeOptimalRequest(test::randomPolygon(rng, 6, 0.9), Bounds4{ 0.5, 0.8, 1.0, 1.5 });
  r.curve = "interpolating";
  const double optimal = generate(r, test::unhurriedLimits()).duration;
  r.timing = "stretch";
  const double stretched = generate(r, test::unhurriedLimits()).duration;
  r.timing = "";
  EXPECT_EQ(generate(r, test::unhurriedLimits()).duration, stretched) << "stretch is the default";
  EXPECT_LT(optimal, stretched);
}

TEST(TimeOptimal, DwellAndStationaryEndsAreTimed)
{
  // A dwell (identical waypoints with explicit times) and a clamped spline with zero end
  // velocities (C′ = 0 at both ends): the motion is finite, bounded and at rest at the ends.
  const Bounds4 b{ 0.5, 0.5, 1.0, 1.0 };
  TrajectoryRequest r = timeOptimalRequest({ pose(0.0, Eigen::Vector3d(0, 0, 0)), pose(0.5, Eigen::Vector3d(1, 0, 0)),
                                             pose(0.5, Eigen::Vector3d(1, 0, 0)), pose(1.0, Eigen::Vector3d(1, 1, 0)) },
                                           b);
  r.times = { 0, 1, 2, 3 };
  r.sample_count = 2000;
  TrajectoryResult out = generate(r, test::unhurriedLimits());
  expectWithinBounds(out, b, "dwell");
  r.curve = "interpolating";
  r.end_condition = "clamped";
  r.waypoints.erase(r.waypoints.begin() + 2);
  r.times = { 0, 1, 3 };
  out = generate(r, test::unhurriedLimits());
  expectWithinBounds(out, b, "clamped");
  EXPECT_TRUE(std::isfinite(out.duration));
}

// ---- Errors ------------------------------------------------------------------------------

TEST(TimeOptimal, MissingBoundsAreErrorsNamingThem)
{
  const Eigen::Vector3d p(0, 0, 0);
  // A pure rotation with linear bounds only.
  std::string e = errorOf(timeOptimalRequest({ pose(0.0, p), pose(1.0, p) }, Bounds4{ 1.0, 0.0, 1.0, 0.0 }));
  EXPECT_EQ(e.find("max_angular_velocity"), 0U) << e;
  EXPECT_NE(e.find("max_angular_acceleration"), std::string::npos) << e;
  // No bound at all.
  e = errorOf(timeOptimalRequest({ pose(0.0, p), pose(1.0, Eigen::Vector3d(1, 0, 0)) }, Bounds4{}));
  EXPECT_EQ(e.find("max_linear_velocity"), 0U) << e;
  // A speed bound but no acceleration bound: cannot start at rest.
  e = errorOf(timeOptimalRequest({ pose(0.0, p), pose(0.0, Eigen::Vector3d(1, 0, 0)) }, Bounds4{ 1.0, 0, 0, 0 }));
  EXPECT_EQ(e.find("max_linear_acceleration"), 0U) << e;
  // Unknown timing names.
  TrajectoryRequest r =
      timeOptimalRequest({ pose(0.0, p), pose(0.0, Eigen::Vector3d(1, 0, 0)) }, Bounds4{ 1, 1, 1, 1 });
  r.timing = "fastest";
  e = errorOf(r);
  EXPECT_EQ(e.find("timing"), 0U) << e;
  EXPECT_NE(e.find("stretch, time_optimal"), std::string::npos) << e;
  // The sphere: max_angular_acceleration is needed.
  SphereRequest s;
  s.waypoints = { Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0) };
  s.timing = "time_optimal";
  s.max_angular_velocity = 1.0;
  try
  {
    generate(s, test::unhurriedLimits());
    ADD_FAILURE() << "no error";
  }
  catch (const InvalidInputError& err)
  {
    EXPECT_EQ(std::string(err.what()).find("max_angular_acceleration"), 0U) << err.what();
  }
}
