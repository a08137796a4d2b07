// The closed-form timing of geodesic chains (timing/geodesic_timing.h). Checked against what is
// computed independently here: the trapezoid and the double S from the textbook's cases
// (L. Biagiotti, C. Melchiorri, "Trajectory Planning for Automatic Machines and Robots", §3.2.2,
// §3.4) in the scalar bounds of each segment, the general timings (time_optimal.h, jerk_limited.h)
// run on the same path, the bounds at 1 kHz on the motion's own jets and by finite differences, and
// the planner's response (rest at the ends, the waypoints at their reported times, the figures).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/timing/geodesic_timing.h"
#include "se3_interpolation/timing/jerk_limited.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "test_utils.h"

using namespace se3_interpolation;
using timing::RateBounds;

namespace
{
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- Independent references -------------------------------------------------------------------

/// The rest-to-rest trapezoid over L under ṡ ≤ v (∞: none), |s̈| ≤ a: a cruise when L ≥ v²/a.
double trapezoidDuration(double L, double v, double a)
{
  if (std::isfinite(v) && L >= v * v / a)
    return L / v + v / a;
  return 2.0 * std::sqrt(L / a);
}

/// The rest-to-rest double S over L under v, a, j (∞: none for v or a, not both), from the cases of
/// Biagiotti & Melchiorri §3.4 with v0 = v1 = 0.
double doubleSDuration(double L, double v, double a, double j)
{
  if (std::isfinite(v))
  {
    const bool a_reached = v * j >= a * a;
    const double tj = a_reached ? a / j : std::sqrt(v / j);
    const double ta = a_reached ? tj + v / a : 2.0 * tj;
    if (L / v - ta >= 0.0)
      return ta + L / v;
  }
  if (std::isfinite(a))
  {
    const double tj = a / j;
    const double ta = 0.5 * (tj + std::sqrt(tj * tj + 4.0 * L / a));
    if (ta >= 2.0 * tj)
      return 2.0 * ta;
  }
  return 4.0 * std::cbrt(L / (2.0 * j));
}

/// The scalar bound of one kind over the channels that move at rates r (0 = unbounded).
double scalar(const std::array<double, 2>& bound, const std::array<double, 2>& r)
{
  double s = kInf;
  for (int c = 0; c < 2; ++c)
    if (bound[c] > 0.0 && r[c] > 0.0)
      s = std::min(s, bound[c] / r[c]);
  return s;
}

/// The reference duration of a rest-to-rest segment of path-time length L whose channels move at
/// rates r (|C′_c|) under the six bounds.
double referenceDuration(double L, const std::array<double, 2>& r, const RateBounds& b)
{
  const double v = scalar(b.velocity, r), a = scalar(b.acceleration, r), j = scalar(b.jerk, r);
  return std::isfinite(j) ? doubleSDuration(L, v, a, j) : trapezoidDuration(L, v, a);
}

/// The rates |C′_c| of the geodesic A → B traversed in one unit of path time.
std::array<double, 2> rates(const Pose<double>& a, const Pose<double>& b)
{
  return { (b.p - a.p).norm(), rotationAngle(Quaternion<double>(a.q.conjugate() * b.q)) };
}

RateBounds bounds(double v, double w, double a, double alpha, double j, double jw)
{
  RateBounds b;
  b.velocity = { v, w };
  b.acceleration = { a, alpha };
  b.jerk = { j, jw };
  return b;
}

template <class G>
std::shared_ptr<const Curve<G>> polyline(const std::vector<Pose<double>>& points, std::vector<double> times = {})
{
  if (times.empty())
    for (std::size_t i = 0; i < points.size(); ++i)
      times.push_back(static_cast<double>(i));
  return std::make_shared<PiecewiseGeodesic<G>>(points, times);
}

Pose<double> pose(const Eigen::Vector3d& rotation, const Eigen::Vector3d& p)
{
  return Pose<double>(so3Exp<double>(rotation), p);
}

/// log-uniform in [lo, hi].
double logUniform(std::mt19937& rng, double lo, double hi)
{
  return std::exp(std::uniform_real_distribution<double>(std::log(lo), std::log(hi))(rng));
}

/// Six random bounds, each channel's own scale; a jerk bound only with `jerk`.
RateBounds randomBounds(std::mt19937& rng, bool jerk)
{
  return bounds(logUniform(rng, 0.1, 3.0), logUniform(rng, 0.1, 3.0), logUniform(rng, 0.1, 3.0),
                logUniform(rng, 0.1, 3.0), jerk ? logUniform(rng, 0.5, 30.0) : 0.0,
                jerk ? logUniform(rng, 0.5, 30.0) : 0.0);
}

/// The velocity, acceleration and jerk norms per channel at t (third-order jets of the motion).
timing::Kinematics3 kinematics3At(const Curve<DoubleGeodesicSe3>& c, double t, Side side)
{
  return timing::kinematics3FromJet(jet3Of(c, Jet<3>::variable(t), side));
}
template <class G>
timing::Kinematics3 kinematics3At(const Curve<G>& c, double t, Side side)
{
  return timing::kinematics3FromJet(jet3Of(c, Jet<3>::variable(t), side));
}

/// Every bound at 1 kHz (and at least 2000 samples) on the motion's third-order jets, and the
/// accelerations and jerks by finite differences of its velocities and accelerations (their means
/// over a step: at most the peaks), within 1e-9 relative. Returns the largest ratio to a bound.
template <class G>
double expectWithinBounds(const Curve<G>& c, const RateBounds& b)
{
  const double t0 = c.startTime(), t1 = c.endTime();
  const std::size_t n = std::max<std::size_t>(2000, static_cast<std::size_t>((t1 - t0) * 1000.0));
  const double dt = (t1 - t0) / static_cast<double>(n);
  double worst = 0.0;
  const auto check = [&](double value, double bound, double slack, const char* what, double t) {
    if (!(bound > 0.0))
      return;
    worst = std::max(worst, value / bound);
    EXPECT_LE(value, bound * (1.0 + 1e-9) + slack) << what << " at t = " << t;
  };
  timing::Kinematics3 prev = kinematics3At(c, t0, Side::kRight);
  for (std::size_t i = 0; i <= n; ++i)
  {
    const double t = i == n ? t1 : t0 + dt * static_cast<double>(i);
    const timing::Kinematics3 k = kinematics3At(c, t, i == n ? Side::kLeft : Side::kRight);
    const Twist* parts[3] = { &k.velocity, &k.acceleration, &k.jerk };
    for (int order = 0; order < 3; ++order)
    {
      const std::array<double, 2>& bound = order == 0 ? b.velocity : order == 1 ? b.acceleration : b.jerk;
      check(parts[order]->linear.norm(), bound[0], 1e-300, "rate (linear)", t);
      check(parts[order]->angular.norm(), bound[1], 1e-300, "rate (angular)", t);
    }
    if (i > 0)
    {
      const double h = t - (t0 + dt * static_cast<double>(i - 1));
      // Rounding of two values of size |v| (resp. |a|) over the step.
      check((k.velocity.linear - prev.velocity.linear).norm() / h, b.acceleration[0],
            1e-15 * k.velocity.linear.norm() / h, "difference of velocities (linear)", t);
      check((k.velocity.angular - prev.velocity.angular).norm() / h, b.acceleration[1],
            1e-15 * k.velocity.angular.norm() / h, "difference of velocities (angular)", t);
      check((k.acceleration.linear - prev.acceleration.linear).norm() / h, b.jerk[0],
            1e-15 * k.acceleration.linear.norm() / h, "difference of accelerations (linear)", t);
      check((k.acceleration.angular - prev.acceleration.angular).norm() / h, b.jerk[1],
            1e-15 * k.acceleration.angular.norm() / h, "difference of accelerations (angular)", t);
    }
    prev = k;
  }
  return worst;
}

/// At rest at both ends: outside the motion exactly; inside it zero velocity and, with a jerk bound
/// (a continuous acceleration), zero acceleration, to the rounding of the time from a run's start.
template <class G>
void expectRestAtEnds(const Curve<G>& c, bool jerk)
{
  for (const auto& [t, side] : { std::pair<double, Side>{ c.startTime(), Side::kLeft },
                                 std::pair<double, Side>{ c.startTime(), Side::kRight },
                                 std::pair<double, Side>{ c.endTime(), Side::kLeft },
                                 std::pair<double, Side>{ c.endTime(), Side::kRight } })
  {
    const Kinematics k = kinematicsAt(c, t, side);
    const double v = k.velocity.linear.norm() + k.velocity.angular.norm();
    const double a = k.acceleration.linear.norm() + k.acceleration.angular.norm();
    if ((t == c.startTime()) == (side == Side::kLeft))
    {
      EXPECT_EQ(v, 0.0) << "t = " << t;
      EXPECT_EQ(a, 0.0) << "t = " << t;
      continue;
    }
    EXPECT_LE(v, 1e-12) << "t = " << t;
    if (jerk)
    {
      EXPECT_LE(a, 1e-12) << "t = " << t;
    }
  }
}

/// The general timing of the same path: jerk-limited with a jerk bound, else time-optimal.
template <class G>
double generalDuration(const std::shared_ptr<const Curve<G>>& path, const RateBounds& b)
{
  if (b.jerk[0] > 0.0 || b.jerk[1] > 0.0)
  {
    const auto timed = timing::makeJerkLimitedCurve<G>(path, b);
    return timed->endTime() - timed->startTime();
  }
  const auto timed = timing::makeTimeOptimalCurve<G>(path, b);
  return timed->endTime() - timed->startTime();
}

/// The general timing's duration against the exact one: never shorter; at most 1 % longer (its
/// tolerance, docs/timing.md) where one channel's bounds decide the whole double S or there is no
/// jerk bound. Where translation and rotation both move under jerk bounds and different channels
/// bind (the speed in one, the jerk in the other), the general timing's window τ = max_c a′_c / j_c
/// (jerk_limited.h) is longer than the scalar double S's min(A, √(V J)) / J: it is up to a third
/// slower there, and only "never shorter" is checked.
void expectGeneral(double general, double exact, bool one_channel_decides)
{
  EXPECT_GE(general, exact * (1.0 - 1e-9));
  if (one_channel_decides)
  {
    EXPECT_LE(general, exact * 1.01);
  }
}

/// Whether the general timing is held to its 1 % here (expectGeneral).
bool oneChannelDecides(const std::array<double, 2>& r, const RateBounds& b)
{
  return !(r[0] > 0.0 && r[1] > 0.0) || !(b.jerk[0] > 0.0 || b.jerk[1] > 0.0);
}

template <class G>
std::shared_ptr<const timing::GeodesicTimedCurve<G>> closedForm(const std::shared_ptr<const Curve<G>>& path,
                                                                const RateBounds& b)
{
  auto timed = timing::makeGeodesicTimedCurve<G>(path, b);
  EXPECT_TRUE(timed != nullptr);
  return timed;
}

TrajectoryRequest lineRequest(const std::vector<Pose<double>>& waypoints, const RateBounds& b)
{
  TrajectoryRequest r;
  r.waypoints = waypoints;
  r.curve = "piecewise_geodesic";
  r.timing = "time_optimal";
  r.max_linear_velocity = b.velocity[0];
  r.max_angular_velocity = b.velocity[1];
  r.max_linear_acceleration = b.acceleration[0];
  r.max_angular_acceleration = b.acceleration[1];
  r.max_linear_jerk = b.jerk[0];
  r.max_angular_jerk = b.jerk[1];
  r.sample_period = 1e-3;
  return r;
}

// ---- The 1-DOF profile ------------------------------------------------------------------------

TEST(RestToRestProfile, DurationsAreTheTextbooksInEveryCase)
{
  std::mt19937 rng(54);
  for (int i = 0; i < 4000; ++i)
  {
    const double L = logUniform(rng, 1e-9, 1e6);
    const double v = i % 5 == 0 ? kInf : logUniform(rng, 1e-3, 1e3);
    const double a = logUniform(rng, 1e-3, 1e3);
    const double j = i % 2 == 0 ? kInf : logUniform(rng, 1e-3, 1e4);
    const auto p = timing::restToRestProfile(L, v, a, j);
    ASSERT_TRUE(p.has_value());
    const double expected = std::isfinite(j) ? doubleSDuration(L, v, a, j) : trapezoidDuration(L, v, a);
    EXPECT_NEAR(p->duration(), expected, 1e-9 * expected) << "L " << L << " v " << v << " a " << a << " j " << j;
    EXPECT_EQ(p->position(p->duration(), Side::kLeft), L);
  }
  // Unbounded acceleration with a jerk and a speed bound: the acceleration √(v j) is reached.
  const auto p = timing::restToRestProfile(10.0, 1.0, kInf, 4.0);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->duration(), doubleSDuration(10.0, 1.0, kInf, 4.0), 1e-12);
  EXPECT_NEAR(p->peak_acceleration, 2.0, 1e-15);
  // No finite motion: neither an acceleration bound nor (speed and jerk).
  EXPECT_FALSE(timing::restToRestProfile(1.0, 1.0, kInf, kInf).has_value());
  EXPECT_FALSE(timing::restToRestProfile(1.0, kInf, kInf, 3.0).has_value());
  EXPECT_FALSE(timing::restToRestProfile(0.0, 1.0, 1.0, 1.0).has_value());
}

TEST(RestToRestProfile, JetsKeepTheBoundsAndAreContinuousAcrossPhases)
{
  std::mt19937 rng(7);
  for (int i = 0; i < 300; ++i)
  {
    const double L = logUniform(rng, 1e-3, 1e3), v = logUniform(rng, 1e-2, 1e2), a = logUniform(rng, 1e-2, 1e2);
    const double j = i % 3 == 0 ? kInf : logUniform(rng, 1e-2, 1e3);
    const timing::RestToRestProfile p = *timing::restToRestProfile(L, v, a, j);
    const double T = p.duration();
    const int n = 2000;
    double previous = 0.0;
    for (int k = 0; k <= n; ++k)
    {
      const Jet<3> s = p.position(Jet<3>::variable(T * k / n), Side::kRight);
      EXPECT_GE(s.value(), previous - 1e-15 * L);
      previous = s.value();
      EXPECT_LE(s.coefficient(1), v * (1.0 + 1e-12));
      EXPECT_GE(s.coefficient(1), -1e-15 * v);
      EXPECT_LE(std::abs(2.0 * s.coefficient(2)), a * (1.0 + 1e-12));
      if (std::isfinite(j))
      {
        EXPECT_LE(std::abs(6.0 * s.coefficient(3)), j * (1.0 + 1e-12));
      }
    }
    // Position and speed continuous at every switch (and the acceleration too with a jerk bound), to
    // the rounding of the switch times (T − τ of the mirrored half: a few ulps of T).
    for (double t : { p.t_j, p.t_a - p.t_j, p.t_a, p.t_a + p.t_v, T - p.t_a + p.t_j, T - p.t_j, 0.5 * T })
    {
      const Jet<3> l = p.position(Jet<3>::variable(t), Side::kLeft);
      const Jet<3> r = p.position(Jet<3>::variable(t), Side::kRight);
      const double dt = 1e-15 * T;
      EXPECT_NEAR(l.value(), r.value(), 1e-12 * L + dt * p.peak_speed) << "t = " << t;
      EXPECT_NEAR(l.coefficient(1), r.coefficient(1), 1e-12 * p.peak_speed + dt * p.peak_acceleration) << "t = " << t;
      if (std::isfinite(j))
      {
        EXPECT_NEAR(2.0 * l.coefficient(2), 2.0 * r.coefficient(2), 1e-12 * p.peak_acceleration + dt * j)
            << "t = " << t;
      }
    }
    // The inverse, and the energy ∫ s̈² dt by Simpson's rule on each phase (s̈ is linear there: exact
    // but for the ends, taken 1e-9 of the phase inside it: a switch time computed two ways may
    // differ by an ulp).
    EXPECT_NEAR(p.position(p.timeAt(0.3 * L), Side::kRight), 0.3 * L, 1e-12 * L);
    const double switches[] = { 0.0, p.t_j, p.t_a - p.t_j, p.t_a, p.t_a + p.t_v, T - p.t_a + p.t_j, T - p.t_j, T };
    const auto acc = [&p](double t, Side side) { return 2.0 * p.position(Jet<3>::variable(t), side).coefficient(2); };
    double energy = 0.0;
    for (int k = 0; k + 1 < 8; ++k)
    {
      const double t0 = switches[k], t1 = switches[k + 1], inset = 1e-9 * (t1 - t0);
      const double a0 = acc(t0 + inset, Side::kRight), am = acc(0.5 * (t0 + t1), Side::kRight);
      const double a1 = acc(t1 - inset, Side::kLeft);
      energy += (t1 - t0) / 6.0 * (a0 * a0 + 4.0 * am * am + a1 * a1);
    }
    EXPECT_NEAR(p.accelerationEnergy(), energy, 1e-8 * p.accelerationEnergy())
        << "L " << L << " v " << v << " a " << a << " j " << j;
  }
}

// ---- Two-pose moves ----------------------------------------------------------------------------

/// A two-pose double-geodesic move under random bounds: the textbook duration in the scalar bounds
/// (1e-9), the general timing's (expectGeneral), every bound at 1 kHz, rest at both ends. Every
/// third move translates only, every third rotates only.
void checkTwoPoseMoves(bool jerk)
{
  std::mt19937 rng(jerk ? 541 : 542);
  for (int i = 0; i < 15; ++i)
  {
    const Pose<double> a = test::randomPose(rng);
    Pose<double> b = test::randomPose(rng);
    if (i % 3 == 1)
      b.q = a.q;
    else if (i % 3 == 2)
      b.p = a.p;
    const RateBounds bnd = randomBounds(rng, jerk);
    const auto path = polyline<DoubleGeodesicSe3>({ a, b });
    const auto timed = closedForm(path, bnd);
    ASSERT_TRUE(timed);
    const double duration = timed->endTime() - timed->startTime();
    const double reference = referenceDuration(1.0, rates(a, b), bnd);
    EXPECT_NEAR(duration, reference, 1e-9 * reference) << "case " << i;
    expectGeneral(generalDuration(path, bnd), duration, oneChannelDecides(rates(a, b), bnd));
    const double worst = expectWithinBounds(*timed, bnd);
    EXPECT_GT(worst, 1.0 - 1e-9) << "case " << i << ": no bound is reached";
    expectRestAtEnds(*timed, jerk);
  }
}

TEST(GeodesicTiming, TwoPoseMovesAreTheTrapezoid) { checkTwoPoseMoves(false); }
TEST(GeodesicTiming, TwoPoseMovesAreTheDoubleS) { checkTwoPoseMoves(true); }

TEST(GeodesicTiming, ScrewSegmentsAreTakenOnlyWithoutCentripetalAcceleration)
{
  const RateBounds b = bounds(0.5, 1.0, 1.0, 2.0, 5.0, 10.0);
  const Pose<double> origin = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  // Pure translation, pure rotation about an axis through the origin, a screw along such an axis.
  const std::vector<Pose<double>> accepted = { pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 2.0, -0.5)),
                                               pose(Eigen::Vector3d(0.3, -1.2, 0.4), Eigen::Vector3d::Zero()),
                                               pose(Eigen::Vector3d(0.0, 0.0, 2.0), Eigen::Vector3d(0.0, 0.0, 0.7)) };
  for (const Pose<double>& end : accepted)
  {
    const auto path = polyline<ScrewSe3>({ origin, end });
    const auto timed = closedForm(path, b);
    ASSERT_TRUE(timed);
    const double reference = referenceDuration(1.0, rates(origin, end), b);
    EXPECT_NEAR(timed->endTime() - timed->startTime(), reference, 1e-9 * reference);
    expectGeneral(generalDuration(path, b), reference, oneChannelDecides(rates(origin, end), b));
    expectWithinBounds(*timed, b);
    expectRestAtEnds(*timed, true);
  }
  // A rotation with a translation across its axis: the screw bends, no closed form.
  const Pose<double> across = pose(Eigen::Vector3d(0.0, 0.0, 1.0), Eigen::Vector3d(1.0, 0.0, 0.0));
  const auto bent = polyline<ScrewSe3>({ origin, across });
  EXPECT_FALSE(timing::geodesicChain(*bent).has_value());
  EXPECT_EQ(timing::makeGeodesicTimedCurve<ScrewSe3>(bent, b), nullptr);
  // ... but the same poses in the double geodesic are a straight segment.
  EXPECT_TRUE(timing::geodesicChain(*polyline<DoubleGeodesicSe3>({ origin, across })).has_value());
}

TEST(GeodesicTiming, OnlyGeodesicChainsAreTaken)
{
  std::mt19937 rng(3);
  const std::vector<Pose<double>> p = test::randomPolygon(rng, 3);
  const std::vector<double> times{ 0.0, 1.0, 2.0 };
  EXPECT_TRUE(timing::geodesicChain(*polyline<DoubleGeodesicSe3>(p, times)).has_value());
  EXPECT_TRUE(timing::geodesicChain(BezierCurve<DoubleGeodesicSe3>({ p[0], p[1] }, 0.0, 2.0)).has_value());
  EXPECT_FALSE(timing::geodesicChain(BezierCurve<DoubleGeodesicSe3>(p, 0.0, 2.0)).has_value());
  // A dwell (two equal waypoints at different times) is the general timing's.
  EXPECT_FALSE(timing::geodesicChain(*polyline<DoubleGeodesicSe3>({ p[0], p[1], p[1] }, times)).has_value());
}

// ---- Chains ------------------------------------------------------------------------------------

TEST(GeodesicTiming, ChainsStopAtEveryCornerAndPassTheWaypointsAtTheirTimes)
{
  std::mt19937 rng(11);
  for (bool jerk : { false, true })
  {
    const std::vector<Pose<double>> points = test::randomPolygon(rng, 5);
    const std::vector<double> times{ 0.0, 0.7, 2.0, 2.5, 4.0 };
    const RateBounds b = randomBounds(rng, jerk);
    const auto path = polyline<DoubleGeodesicSe3>(points, times);
    const auto timed = closedForm(path, b);
    ASSERT_TRUE(timed);
    ASSERT_EQ(timed->profile().runs.size(), 4u);
    double reference = 0.0;
    for (std::size_t i = 0; i + 1 < points.size(); ++i)
    {
      const std::array<double, 2> r = rates(points[i], points[i + 1]);
      const double dt = times[i + 1] - times[i];
      reference += referenceDuration(dt, { r[0] / dt, r[1] / dt }, b);
    }
    EXPECT_NEAR(timed->endTime() - timed->startTime(), reference, 1e-9 * reference);
    expectGeneral(generalDuration<DoubleGeodesicSe3>(path, b), reference, !jerk);
    expectWithinBounds(*timed, b);
    expectRestAtEnds(*timed, b.jerk[0] > 0.0 || b.jerk[1] > 0.0);
    // Through the planner: each waypoint at its reported time, at rest there.
    const TrajectoryResult out = generate(lineRequest(points, b), test::unhurriedLimits());
    EXPECT_NEAR(out.duration, reference, 1e-9 * reference);
    ASSERT_EQ(out.waypoint_times.size(), points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      const TrajectorySample s = out.state_at(out.waypoint_times[i]);
      EXPECT_LT(test::poseDistance(s.pose, points[i]), 1e-12) << "waypoint " << i;
      EXPECT_EQ(s.velocity.linear.norm() + s.velocity.angular.norm(), 0.0) << "waypoint " << i;
    }
  }
}

TEST(GeodesicTiming, CollinearWaypointsAtTheChordRateAreOneRun)
{
  // Equally spaced on a line at equal times: C′ does not jump, the general timing does not stop.
  std::vector<Pose<double>> points;
  for (int i = 0; i < 4; ++i)
    points.push_back(pose(Eigen::Vector3d(0.0, 0.0, 0.2 * i), Eigen::Vector3d(0.5 * i, 0.0, 0.0)));
  const RateBounds b = bounds(0.5, 1.0, 1.0, 2.0, 5.0, 10.0);
  const auto path = polyline<DoubleGeodesicSe3>(points);
  const auto timed = closedForm(path, b);
  ASSERT_TRUE(timed);
  EXPECT_EQ(timed->profile().runs.size(), 1u);
  const double reference = referenceDuration(3.0, { 0.5, 0.2 }, b);
  EXPECT_NEAR(timed->endTime() - timed->startTime(), reference, 1e-9 * reference);
  expectGeneral(generalDuration<DoubleGeodesicSe3>(path, b), reference, false);
  // The interior waypoints at their reported times.
  for (int i = 1; i < 3; ++i)
  {
    const double t = timed->profile().timeAt(static_cast<double>(i));
    EXPECT_LT(test::poseDistance(timed->value(t), points[i]), 1e-12) << "waypoint " << i;
  }
}

// ---- Hard points -------------------------------------------------------------------------------

TEST(GeodesicTiming, HardPoints)
{
  const RateBounds all = bounds(0.5, 1.0, 1.0, 2.0, 5.0, 10.0);
  const Pose<double> o = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  struct Case
  {
    const char* name;
    Pose<double> end;
    RateBounds b;
  };
  const std::vector<Case> cases = {
    { "zero rotation", pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, -2.0, 0.5)), all },
    { "zero translation", pose(Eigen::Vector3d(0.4, 0.1, -1.0), Eigen::Vector3d::Zero()), all },
    { "rotation pi - 1e-9", pose((M_PI - 1e-9) * Eigen::Vector3d(0.0, 0.6, 0.8), Eigen::Vector3d(0.3, 0.0, 0.0)), all },
    { "tiny distance", pose(Eigen::Vector3d(1e-10, 0.0, 0.0), Eigen::Vector3d(1e-9, 0.0, 0.0)), all },
    { "huge distance", pose(Eigen::Vector3d(0.0, 0.0, 1.0), Eigen::Vector3d(1e6, 0.0, 0.0)), all },
    { "angular channel unbounded", pose(Eigen::Vector3d(0.0, 2.0, 0.0), Eigen::Vector3d(0.0, 1.0, 0.0)),
      bounds(0.5, 0.0, 1.0, 0.0, 5.0, 0.0) },
    { "no speed bounds", pose(Eigen::Vector3d(0.0, 2.0, 0.0), Eigen::Vector3d(0.0, 1.0, 0.0)),
      bounds(0.0, 0.0, 1.0, 2.0, 5.0, 10.0) },
    { "jerk on one channel only", pose(Eigen::Vector3d(0.0, 2.0, 0.0), Eigen::Vector3d(0.0, 1.0, 0.0)),
      bounds(0.5, 1.0, 1.0, 2.0, 0.0, 10.0) },
  };
  for (const Case& c : cases)
  {
    SCOPED_TRACE(c.name);
    const auto path = polyline<DoubleGeodesicSe3>({ o, c.end });
    const auto timed = closedForm(path, c.b);
    ASSERT_TRUE(timed);
    const double reference = referenceDuration(1.0, rates(o, c.end), c.b);
    EXPECT_NEAR(timed->endTime() - timed->startTime(), reference, 1e-9 * reference);
    expectGeneral(generalDuration<DoubleGeodesicSe3>(path, c.b), reference, oneChannelDecides(rates(o, c.end), c.b));
    if (reference < 1e3)
      expectWithinBounds(*timed, c.b);
    expectRestAtEnds(*timed, c.b.jerk[0] > 0.0 || c.b.jerk[1] > 0.0);
    EXPECT_LT(test::poseDistance(timed->value(timed->endTime()), c.end), 1e-12 * (1.0 + c.end.p.norm()));
  }
}

TEST(GeodesicTiming, BoundsThatTheGeneralTimingRefusesAreLeftToIt)
{
  const Pose<double> o = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const Pose<double> end = pose(Eigen::Vector3d(0.0, 1.0, 0.0), Eigen::Vector3d(1.0, 0.0, 0.0));
  const auto path = polyline<DoubleGeodesicSe3>({ o, end });
  EXPECT_EQ(timing::makeGeodesicTimedCurve<DoubleGeodesicSe3>(path, bounds(1.0, 1.0, 0.0, 0.0, 0.0, 0.0)), nullptr);
  EXPECT_EQ(timing::makeGeodesicTimedCurve<DoubleGeodesicSe3>(path, bounds(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)), nullptr);
  EXPECT_EQ(timing::makeGeodesicTimedCurve<DoubleGeodesicSe3>(path, bounds(1.0, 0.0, 0.0, 0.0, 0.0, 3.0)), nullptr);
  EXPECT_EQ(timing::makeGeodesicTimedCurve<DoubleGeodesicSe3>(path, bounds(-1.0, 0.0, 1.0, 0.0, 0.0, 0.0)), nullptr);
  // Through the planner the refusal is the general timing's, naming the bound.
  TrajectoryRequest r = lineRequest(path->controlPoints(), bounds(1.0, 1.0, 0.0, 0.0, 0.0, 0.0));
  try
  {
    generate(r, test::unhurriedLimits());
    ADD_FAILURE() << "served without an acceleration bound";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("max_linear_acceleration"), std::string::npos) << e.what();
  }
}

// ---- The planner's response --------------------------------------------------------------------

TEST(GeodesicTiming, PlannerFiguresAreTheClosedForms)
{
  const Pose<double> a = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const Pose<double> b = pose(Eigen::Vector3d(0.0, 0.0, 1.5), Eigen::Vector3d(2.0, 1.0, 0.0));
  for (bool jerk : { false, true })
  {
    const RateBounds bnd = bounds(0.5, 1.0, 1.0, 2.0, jerk ? 5.0 : 0.0, jerk ? 10.0 : 0.0);
    TrajectoryRequest r = lineRequest({ a, b }, bnd);
    r.rotation_scale = 0.5;
    const TrajectoryResult out = generate(r, test::unhurriedLimits());
    const double reference = referenceDuration(1.0, rates(a, b), bnd);
    EXPECT_NEAR(out.duration, reference, 1e-9 * reference);
    EXPECT_NEAR(out.figures.length, std::sqrt(5.0), 1e-14);
    EXPECT_NEAR(out.figures.rotation_length, 1.5, 1e-14);
    // Peaks and ∫|p̈|² + ρ²|ω̇|² dt from the 1 kHz samples (Simpson's rule on the sampled |a|²).
    double v[2] = {}, acc[2] = {}, energy = 0.0;
    const std::size_t n = out.samples.size();
    for (std::size_t i = 0; i < n; ++i)
    {
      const TrajectorySample& s = out.samples[i];
      v[0] = std::max(v[0], s.velocity.linear.norm());
      v[1] = std::max(v[1], s.velocity.angular.norm());
      acc[0] = std::max(acc[0], s.acceleration.linear.norm());
      acc[1] = std::max(acc[1], s.acceleration.angular.norm());
      const double e = s.acceleration.linear.squaredNorm() + 0.25 * s.acceleration.angular.squaredNorm();
      const double dt = i + 1 < n ? out.samples[i + 1].time - s.time : 0.0;
      energy += e * dt;
    }
    EXPECT_NEAR(out.figures.max_linear_speed, v[0], 1e-3 * v[0]);
    EXPECT_NEAR(out.figures.max_angular_speed, v[1], 1e-3 * v[1]);
    EXPECT_NEAR(out.figures.max_linear_acceleration, acc[0], 1e-9 * acc[0]);
    EXPECT_NEAR(out.figures.max_angular_acceleration, acc[1], 1e-9 * acc[1]);
    EXPECT_NEAR(out.figures.energy, energy, 1e-2 * energy);
    EXPECT_EQ(out.figures.max_linear_jerk > 0.0, jerk);
    EXPECT_EQ(out.samples.front().velocity.linear.norm(), 0.0);
    EXPECT_EQ(out.samples.back().velocity.linear.norm(), 0.0);
    EXPECT_LT(test::poseDistance(out.samples.back().pose, b), 1e-12);
  }
}

TEST(GeodesicTiming, SampleToleranceRefinesTheClosedFormMotion)
{
  const Pose<double> a = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const Pose<double> b = pose(Eigen::Vector3d(0.0, 0.0, 1.0), Eigen::Vector3d(1.0, 0.0, 0.0));
  TrajectoryRequest r = lineRequest({ a, b }, bounds(0.5, 1.0, 1.0, 2.0, 5.0, 10.0));
  r.sample_period = 0.0;
  r.sample_count = 4;
  r.sample_tolerance = 1e-4;
  const TrajectoryResult out = generate(r, test::unhurriedLimits());
  EXPECT_GT(out.samples.size(), 4u);
  for (const TrajectorySample& s : out.samples)
    EXPECT_LT(test::poseDistance(s.pose, out.state_at(s.time).pose), 1e-12);
}

TEST(GeodesicTiming, StretchFiguresAreTheClosedFormsAndTheMeasuredOnes)
{
  const Pose<double> a = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const Pose<double> b = pose(Eigen::Vector3d(0.0, 0.0, 1.5), Eigen::Vector3d(2.0, 1.0, 0.0));
  const Pose<double> c = pose(Eigen::Vector3d(0.5, 0.0, 1.5), Eigen::Vector3d(2.0, 3.0, 0.0));
  TrajectoryRequest r = lineRequest({ a, b, c }, bounds(0.5, 1.0, 0.0, 0.0, 0.0, 0.0));
  r.timing = "stretch";
  r.times = { 0.0, 1.0, 3.0 };
  const TrajectoryResult out = generate(r, test::unhurriedLimits());
  // The speeds on the curve's own clock: √5 m/s and 1.5 rad/s on the first leg, 1 m/s and
  // 0.25 rad/s on the second; the linear speed bound stretches by √5 / 0.5.
  const double k = std::sqrt(5.0) / 0.5;
  EXPECT_NEAR(out.time_scale, k, 1e-14 * k);
  EXPECT_NEAR(out.duration, 3.0 * k, 1e-13 * k);
  EXPECT_NEAR(out.figures.max_linear_speed, 0.5, 1e-15);
  EXPECT_NEAR(out.figures.max_angular_speed, 1.5 / k, 1e-15);
  EXPECT_EQ(out.figures.max_linear_acceleration, 0.0);
  EXPECT_EQ(out.figures.energy, 0.0);
  // The same as measured by quadrature on the curve itself.
  const CurveFigures measured =
      measureCurve(PiecewiseGeodesic<DoubleGeodesicSe3>({ a, b, c }, { 0.0, 1.0, 3.0 }), 1.0);
  EXPECT_NEAR(out.figures.length, measured.length, 1e-12 * measured.length);
  EXPECT_NEAR(out.figures.rotation_length, measured.rotation_length, 1e-12 * measured.rotation_length);
  EXPECT_NEAR(out.figures.max_linear_speed * k, measured.max_linear_speed, 1e-12);
  EXPECT_NEAR(out.figures.max_angular_speed * k, measured.max_angular_speed, 1e-12);
  EXPECT_LT(measured.max_linear_acceleration + measured.max_angular_acceleration, 1e-12);
}

}  // namespace
