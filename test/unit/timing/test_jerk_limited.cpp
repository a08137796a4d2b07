// Jerk-limited timing (timing/jerk_limited.h). Checked against what is computed independently
// here: the rest-to-rest "double S" of straight lines from the textbook formulas (L. Biagiotti,
// C. Melchiorri, "Trajectory Planning for Automatic Machines and Robots", §3.4), a brute-force
// search over jerk-limited profiles along a circle arc whose rates are written out analytically,
// and finite differences of the timed motion's own velocities and accelerations at 10⁵ samples.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/curves/blended_spline.h"
#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/curves/corner_blend.h"
#include "se3_interpolation/curves/hermite.h"
#include "se3_interpolation/curves/interpolating_spline.h"
#include "se3_interpolation/timing/jerk_limited.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "test_utils.h"

using namespace se3_interpolation;
using timing::RateBounds;

namespace
{
// ---- Independent references ------------------------------------------------------------

/// The rest-to-rest double S over distance L with |v| ≤ v, |a| ≤ a, |j| ≤ j (Biagiotti &
/// Melchiorri §3.4, zero boundary velocities): a_max not reached when v j < a² (then
/// T_j = √(v/j), T_a = 2 T_j, else T_j = a/j, T_a = T_j + v/a); v_max reached when
/// T_v = L/v − T_a ≥ 0 (T = 2 T_a + T_v); otherwise T_j = a/j and T_a from the cruise-free
/// profile's quadratic T_a² − T_j T_a − L/a = 0, and, when that T_a < 2 T_j, neither reached:
/// T_j = (L / (2 j))^{1/3}, T_a = 2 T_j (T = 2 T_a).
struct DoubleS
{
  double duration = 0.0;
  bool v_reached = false;
  bool a_reached = false;
};

DoubleS doubleS(double L, double v, double a, double j)
{
  DoubleS r;
  double tj, ta;
  if (v * j >= a * a)
  {
    tj = a / j;
    ta = tj + v / a;
    r.a_reached = true;
  }
  else
  {
    tj = std::sqrt(v / j);
    ta = 2.0 * tj;
  }
  const double tv = L / v - ta;
  if (tv >= 0.0)
  {
    r.v_reached = true;
    r.duration = 2.0 * ta + tv;
    return r;
  }
  tj = a / j;
  ta = 0.5 * (tj + std::sqrt(tj * tj + 4.0 * L / a));
  r.a_reached = ta >= 2.0 * tj;
  if (!r.a_reached)
  {
    tj = std::cbrt(L / (2.0 * j));
    ta = 2.0 * tj;
  }
  r.duration = 2.0 * ta;
  return r;
}

Pose<double> pose(const Eigen::Vector3d& rotation, const Eigen::Vector3d& p)
{
  return Pose<double>(so3Exp<double>(rotation), p);
}

RateBounds bounds(double v, double a, double j, double w, double alpha, double jw)
{
  RateBounds b;
  b.velocity = { v, w };
  b.acceleration = { a, alpha };
  b.jerk = { j, jw };
  return b;
}

template <class G>
std::shared_ptr<const Curve<G>> line(const typename G::template Point<double>& a,
                                     const typename G::template Point<double>& b, double duration = 1.0)
{
  return std::make_shared<PiecewiseGeodesic<G>>(std::vector<typename G::template Point<double>>{ a, b },
                                                std::vector<double>{ 0.0, duration });
}

/// The rates of a motion at an instant: |v|, |a| per channel (pose curves and the sphere).
Rates ratesOf(const Curve<Sphere>& c, double t, Side side = Side::kRight) { return rates(kinematicsAt(c, t, side)); }
template <class G>
Rates ratesOf(const Curve<G>& c, double t, Side side = Side::kRight)
{
  return rates(kinematicsAt(c, t, side));
}

/// Velocity and acceleration vectors of both channels stacked (pose: linear then angular; sphere:
/// the ambient covariant ones), for finite differences.
Eigen::VectorXd velocityOf(const Curve<Sphere>& c, double t) { return kinematicsAt(c, t).velocity; }
Eigen::VectorXd accelerationOf(const Curve<Sphere>& c, double t, Side side = Side::kRight)
{
  return kinematicsAt(c, t, side).acceleration;
}
template <class G>
Eigen::VectorXd velocityOf(const Curve<G>& c, double t)
{
  const Kinematics k = kinematicsAt(c, t);
  Eigen::VectorXd v(6);
  v << k.velocity.linear, k.velocity.angular;
  return v;
}
template <class G>
Eigen::VectorXd accelerationOf(const Curve<G>& c, double t, Side side = Side::kRight)
{
  const Kinematics k = kinematicsAt(c, t, side);
  Eigen::VectorXd v(6);
  v << k.acceleration.linear, k.acceleration.angular;
  return v;
}

template <class G>
std::shared_ptr<const Curve<G>> naturalSpline(const std::vector<typename G::template Point<double>>& points,
                                              const std::vector<double>& times)
{
  using Tangent = typename G::template Tangent<double>;
  const Tangent zero = G::log(points[0], points[0]);
  return makeInterpolatingSpline<G>(points, times, EndCondition::kNatural, zero, zero, zero);
}

/// Times 0.5 … 1.5 s apart.
std::vector<double> unevenTimes(std::size_t n, std::mt19937& rng)
{
  std::vector<double> t{ 0.0 };
  std::uniform_real_distribution<double> u(0.5, 1.5);
  for (std::size_t i = 1; i < n; ++i)
    t.push_back(t.back() + u(rng));
  return t;
}

/// The natural spline through a random polygon of n poses (rotation steps below `step`) at
/// random uneven times, from a fixed seed.
std::shared_ptr<const Curve<DoubleGeodesicSe3>> randomSpline(unsigned seed, std::size_t n, double step)
{
  std::mt19937 rng(seed);
  const std::vector<Pose<double>> points = test::randomPolygon(rng, n, step);
  return naturalSpline<DoubleGeodesicSe3>(points, unevenTimes(n, rng));
}

/// The finite difference of the ambient covariant acceleration on the sphere has a normal part
/// (the covariant jerk is its tangent part); pose motions have none.
void removeNormal(const Curve<Sphere>& c, double t, Eigen::VectorXd* d)
{
  const Eigen::VectorXd x = kinematicsAt(c, t).point;
  *d -= d->dot(x) * x;
}
template <class G>
void removeNormal(const Curve<G>& /*c*/, double /*t*/, Eigen::VectorXd* /*d*/)
{
}

/// The channel blocks of a stacked vector: pose (0..2 linear, 3..5 angular) or sphere (angular).
std::array<double, 2> channelNorms(const Eigen::VectorXd& v)
{
  if (v.size() == 6)
    return { v.head<3>().norm(), v.tail<3>().norm() };
  return { 0.0, v.norm() };
}

/// Checks every bound at n samples: |v|, |a| as reported, and the jerk as the finite difference of
/// the reported accelerations (the mean of the jerk over the step: at most its peak), the
/// acceleration also as the finite difference of the velocities. On the sphere the finite
/// difference of the ambient covariant acceleration differs from the covariant jerk by the
/// normal component ⟨x, ȧ⟩ x = −⟨v, a⟩ x; it is taken out. Returns the largest ratio to a bound
/// of the finite-difference jerk (continuity of the acceleration: a jump would show as an
/// unbounded difference).
template <class G>
double expectWithinBounds(const Curve<G>& c, const RateBounds& b, const std::string& what, std::size_t n = 100000)
{
  const double t0 = c.startTime(), t1 = c.endTime();
  const double dt = (t1 - t0) / static_cast<double>(n);
  Eigen::VectorXd v_prev = velocityOf(c, t0), a_prev = accelerationOf(c, t0);
  double worst_jerk = 0.0;
  double worst = 0.0;
  for (std::size_t i = 1; i <= n; ++i)
  {
    const double t = t0 + dt * static_cast<double>(i);
    const Eigen::VectorXd v = velocityOf(c, t), a = accelerationOf(c, t);
    const std::array<double, 2> vn = channelNorms(v), an = channelNorms(a);
    Eigen::VectorXd da = (a - a_prev) / dt;
    removeNormal(c, t - 0.5 * dt, &da);
    Eigen::VectorXd dv = (v - v_prev) / dt;
    removeNormal(c, t - 0.5 * dt, &dv);
    const std::array<double, 2> jn = channelNorms(da), dvn = channelNorms(dv);
    for (int ch = 0; ch < 2; ++ch)
    {
      if (b.velocity[ch] > 0.0)
        worst = std::max(worst, vn[ch] / b.velocity[ch]);
      if (b.acceleration[ch] > 0.0)
        worst = std::max({ worst, an[ch] / b.acceleration[ch], dvn[ch] / b.acceleration[ch] });
      if (b.jerk[ch] > 0.0)
        worst_jerk = std::max(worst_jerk, jn[ch] / b.jerk[ch]);
    }
    v_prev = v;
    a_prev = a;
  }
  // The finite differences average over a step: the velocity's over the acceleration's peak
  // to O(dt²), which a relative 1e-6 covers at 10⁵ steps.
  EXPECT_LE(worst, 1.0 + 1e-6) << what;
  EXPECT_LE(worst_jerk, 1.0 + 1e-6) << what;
  return worst_jerk;
}

/// The motion rests with zero acceleration at its start and its end.
template <class G>
void expectRestAtEnds(const Curve<G>& c, const std::string& what)
{
  for (const auto& [t, side] : { std::make_pair(c.startTime(), Side::kRight), std::make_pair(c.endTime(), Side::kLeft) })
  {
    const Rates r = ratesOf(c, t, side);
    for (double x : r)
      EXPECT_LE(x, 1e-9) << what << " at " << t;
  }
}

template <class G>
double timeOptimalDuration(const std::shared_ptr<const Curve<G>>& path, RateBounds b)
{
  b.jerk = { 0.0, 0.0 };
  return timing::makeTimeOptimalCurve<G>(path, b)->profile().duration();
}

/// The acceleration is continuous: its one-sided limits agree at every breakpoint of the motion
/// (where s⃛ or the path's C‴ jumps, and at the stops between segments).
template <class G>
void expectContinuousAcceleration(const Curve<G>& c, const std::string& what)
{
  double worst = 0.0, scale = 0.0;
  for (double t : c.breakpoints())
  {
    const Eigen::VectorXd l = accelerationOf(c, t, Side::kLeft), r = accelerationOf(c, t, Side::kRight);
    worst = std::max(worst, (l - r).norm());
    scale = std::max(scale, l.norm());
  }
  EXPECT_LE(worst, 1e-9 * std::max(scale, 1.0)) << what;
}

/// The jerk-limited motion along a path from rest to rest: within every bound (10⁵ samples),
/// with a continuous acceleration, at rest at both ends, and never faster than the
/// acceleration-only optimum.
template <class G>
std::shared_ptr<const timing::JerkLimitedCurve<G>> expectJerkLimited(const std::shared_ptr<const Curve<G>>& path,
                                                                     const RateBounds& b, const std::string& what)
{
  const auto m = timing::makeJerkLimitedCurve<G>(path, b);
  expectWithinBounds(*m, b, what);
  expectContinuousAcceleration(*m, what);
  expectRestAtEnds(*m, what);
  const double optimum = timeOptimalDuration<G>(path, b);
  EXPECT_GE(m->profile().duration(), optimum) << what;
  // (Reported in the test's XML output: how much the jerk bounds cost here, and how much of it
  // the final uniform stretch took.)
  std::string key = what;
  std::replace(key.begin(), key.end(), ' ', '_');
  ::testing::Test::RecordProperty("ratio_to_acceleration_only_" + key, std::to_string(m->profile().duration() / optimum));
  ::testing::Test::RecordProperty("stretch_" + key, std::to_string(m->profile().stretch));
  return m;
}

// ---- Third-order path jets ------------------------------------------------------------

namespace
{
/// C‴ of both channels from the third-order jet against the central difference of C″ from the
/// second-order one, at interior points of every piece (relative to the jerk's scale). Pieces
/// shorter than 1 ms are left out: the difference's step, 1e-5 of the piece, would drown in
/// rounding there.
template <class G>
void expectThirdOrderJetsMatch(const Curve<G>& c, const std::string& what)
{
  const std::vector<double> b = c.breakpoints();
  double worst = 0.0;
  std::size_t checked = 0;
  for (std::size_t i = 0; i + 1 < b.size(); ++i)
    for (double f : { 0.21, 0.5, 0.77 })
    {
      if (b[i + 1] - b[i] < 1e-3)
        continue;
      ++checked;
      const double t = b[i] + f * (b[i + 1] - b[i]);
      const double h = 1e-5 * (b[i + 1] - b[i]);
      const timing::PathJet3 j = timing::pathJet3At(c, t, Side::kRight);
      const Eigen::VectorXd d = (accelerationOf(c, t + h) - accelerationOf(c, t - h)) / (2.0 * h);
      Eigen::VectorXd difference = d;
      removeNormal(c, t, &difference);
      const std::array<double, 2> fd = channelNorms(difference);
      for (int ch = 0; ch < 2; ++ch)
      {
        const double exact = std::sqrt(j[ch].cc);
        worst = std::max(worst, std::abs(exact - fd[ch]) / (1.0 + exact));
      }
    }
  EXPECT_LE(worst, 1e-5) << what;
  EXPECT_GT(checked, 0u) << what;
}
}  // namespace

TEST(JerkLimited, ThirdOrderJetsOfEveryFamilyAreTheDerivativesOfTheAccelerations)
{
  std::mt19937 rng(29);
  const std::vector<Pose<double>> points = test::randomPolygon(rng, 5, 0.8);
  const std::vector<double> times{ 0.0, 0.7, 1.9, 2.5, 4.0 };
  std::vector<Vector6<double>> tangents(points.size(), Vector6<double>::Constant(0.2));
  const auto knots = [](std::size_t n, int m) {
    std::vector<double> k(static_cast<std::size_t>(m), 0.0);
    for (std::size_t i = 0; i + static_cast<std::size_t>(m) <= n; ++i)
      k.push_back(static_cast<double>(i));
    k.resize(n + static_cast<std::size_t>(m) + 1, k.back());
    return k;
  };
  {
    using G = DoubleGeodesicSe3;
    expectThirdOrderJetsMatch(*naturalSpline<G>(points, times), "natural double geodesic");
    expectThirdOrderJetsMatch(HermiteSpline<G>(points, times, tangents), "hermite double geodesic");
    expectThirdOrderJetsMatch(BezierCurve<G>(points, 0.0, 2.0), "bezier double geodesic");
    expectThirdOrderJetsMatch(BSplineCurve<G>(points, 3, knots(points.size(), 3)), "bspline double geodesic");
    expectThirdOrderJetsMatch(BlendedSpline<G>(points, times, 2), "blended double geodesic");
    expectThirdOrderJetsMatch(CornerBlendedGeodesic<G>(points, times, 0.3, 1.0), "corner blend double geodesic");
  }
  {
    using G = ScrewSe3;
    expectThirdOrderJetsMatch(*naturalSpline<G>(points, times), "natural screw");
    expectThirdOrderJetsMatch(HermiteSpline<G>(points, times, tangents), "hermite screw");
    expectThirdOrderJetsMatch(BSplineCurve<G>(points, 3, knots(points.size(), 3)), "bspline screw");
    expectThirdOrderJetsMatch(CornerBlendedGeodesic<G>(points, times, 0.3, 1.0), "corner blend screw");
  }
  {
    std::vector<Eigen::VectorXd> x;
    for (int i = 0; i < 5; ++i)
      x.push_back(test::randomUnitVectorX(rng, 3));
    expectThirdOrderJetsMatch(*naturalSpline<Sphere>(x, times), "natural sphere");
    expectThirdOrderJetsMatch(BezierCurve<Sphere>(x, 0.0, 2.0), "bezier sphere");
  }
  // The timed motion's own third-order jets, too (its jerk is measured from them).
  const RateBounds b = bounds(1.0, 2.0, 5.0, 1.5, 3.0, 8.0);
  expectThirdOrderJetsMatch(*timing::makeJerkLimitedCurve<DoubleGeodesicSe3>(
                                naturalSpline<DoubleGeodesicSe3>(points, times), b),
                            "jerk-limited motion");
}

// ---- Straight lines: the double S in every case ----------------------------------------

struct LineCase
{
  double v, a, j;
  bool v_reached, a_reached;
};

// L = 1: each case of the double S (checked by doubleS itself below).
const LineCase kLineCases[] = {
  { 0.5, 1.0, 10.0, true, true },  // both reached
  { 0.5, 2.0, 2.0, true, false },  // v_max j_max < a_max²
  { 2.0, 1.0, 10.0, false, true },  // short: no cruise
  { 2.0, 2.0, 2.0, false, false },  // short and a_max not reached
  { 0.01, 1.0, 1e-3, true, false },  // a tiny jerk bound
};

template <class G>
void expectDoubleS(const std::shared_ptr<const Curve<G>>& path, const RateBounds& b, const DoubleS& reference,
                   const std::string& what)
{
  const auto motion = timing::makeJerkLimitedCurve<G>(path, b);
  EXPECT_NEAR(motion->profile().duration() / reference.duration, 1.0, 0.01)
      << what << ": " << motion->profile().duration() << " s against " << reference.duration << " s";
  EXPECT_GE(motion->profile().duration(), reference.duration * (1.0 - 1e-6)) << what;
  expectWithinBounds(*motion, b, what, 20000);
  expectRestAtEnds(*motion, what);
}
}  // namespace

TEST(JerkLimited, TheDoubleSReferenceCoversEveryCase)
{
  for (const LineCase& c : kLineCases)
  {
    const DoubleS r = doubleS(1.0, c.v, c.a, c.j);
    EXPECT_EQ(r.v_reached, c.v_reached) << c.v << " " << c.a << " " << c.j;
    EXPECT_EQ(r.a_reached, c.a_reached) << c.v << " " << c.a << " " << c.j;
  }
  // Hand values: both reached, L/v + v/a + a/j; neither, 4 (L/2j)^{1/3}.
  EXPECT_NEAR(doubleS(1.0, 0.5, 1.0, 10.0).duration, 2.0 + 0.5 + 0.1, 1e-12);
  EXPECT_NEAR(doubleS(1.0, 2.0, 2.0, 2.0).duration, 4.0 * std::cbrt(0.25), 1e-12);
}

TEST(JerkLimited, StraightTranslationIsTheDoubleS)
{
  for (const LineCase& c : kLineCases)
  {
    const auto path = line<DoubleGeodesicSe3>(pose({ 0, 0, 0 }, { 0, 0, 0 }), pose({ 0, 0, 0 }, { 0.6, 0.8, 0 }));
    // The rotation does not move: its bounds never act.
    expectDoubleS<DoubleGeodesicSe3>(path, bounds(c.v, c.a, c.j, 1.0, 1.0, 1.0), doubleS(1.0, c.v, c.a, c.j),
                                     "translation v=" + std::to_string(c.v) + " a=" + std::to_string(c.a) +
                                         " j=" + std::to_string(c.j));
  }
}

/// A path that stands still at its ends (the clamped spline through two points with zero end
/// velocities: a line whose parameter speed is 0 at both ends) is still the straight line, whose
/// fastest motion is the double S of its length. Before the path acceleration was capped where
/// C′ vanishes (jerk_limited_runs.cpp, kStationaryGrowth), the stationary ends made the final
/// check stretch such motions hundreds of times; the cap is conservative near the ends (it bounds
/// s̈_T, where the jerk needs only its changes bounded): measured 1.12 to 1.81 times the double S
/// over the five cases, held here to 2 (the 1 % of a uniformly parameterised line is not reached).
TEST(JerkLimited, AClampedLineAtRestIsWithinTwiceTheDoubleS)
{
  using G = DoubleGeodesicSe3;
  const G::Tangent<double> zero = G::log(pose({ 0, 0, 0 }, { 0, 0, 0 }), pose({ 0, 0, 0 }, { 0, 0, 0 }));
  for (const LineCase& c : kLineCases)
  {
    const std::string what =
        "clamped line v=" + std::to_string(c.v) + " a=" + std::to_string(c.a) + " j=" + std::to_string(c.j);
    const auto path = makeInterpolatingSpline<G>({ pose({ 0, 0, 0 }, { 0, 0, 0 }), pose({ 0, 0, 0 }, { 0.6, 0.8, 0 }) },
                                                 { 0.0, 1.0 }, EndCondition::kClamped, zero, zero, zero);
    const RateBounds b = bounds(c.v, c.a, c.j, 1.0, 1.0, 1.0);
    const auto motion = timing::makeJerkLimitedCurve<G>(path, b);
    const double reference = doubleS(1.0, c.v, c.a, c.j).duration;
    EXPECT_GE(motion->profile().duration(), reference * (1.0 - 1e-6)) << what;
    EXPECT_LE(motion->profile().duration(), 2.0 * reference) << what;
    expectWithinBounds(*motion, b, what, 20000);
    expectRestAtEnds(*motion, what);
  }
}

TEST(JerkLimited, RotationAboutAFixedAxisIsTheDoubleS)
{
  for (const LineCase& c : kLineCases)
  {
    const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 2) / 3.0;
    const auto path = line<ScrewSe3>(pose({ 0, 0, 0 }, { 1, 0, 0 }), pose(axis * 1.0, { 1, 0, 0 }));
    // (Screw: a rotation about an axis through p = (1, 0, 0) keeps p; the linear channel rests.)
    expectDoubleS<ScrewSe3>(path, bounds(1.0, 1.0, 1.0, c.v, c.a, c.j), doubleS(1.0, c.v, c.a, c.j),
                            "rotation v=" + std::to_string(c.v) + " a=" + std::to_string(c.a) +
                                " j=" + std::to_string(c.j));
  }
}

TEST(JerkLimited, TranslationWithRotationIsTheDoubleSOfTheBindingChannel)
{
  for (const LineCase& c : kLineCases)
  {
    // 2 m along z while turning 0.5 rad about z: the linear bounds (over 2 m) bind when the
    // angular ones are at least the linear ones / 4 (0.5 rad against 2 m); both geometries are
    // straight here (the screw's axis is the line of motion).
    const Pose<double> a = pose({ 0, 0, 0 }, { 0, 0, 0 }), b = pose({ 0, 0, 0.5 }, { 0, 0, 2 });
    const RateBounds rb = bounds(c.v, c.a, c.j, c.v, c.a, c.j);
    const DoubleS reference = doubleS(2.0, c.v, c.a, c.j);
    expectDoubleS<DoubleGeodesicSe3>(line<DoubleGeodesicSe3>(a, b), rb, reference,
                                     "double geodesic j=" + std::to_string(c.j));
    expectDoubleS<ScrewSe3>(line<ScrewSe3>(a, b), rb, reference, "screw j=" + std::to_string(c.j));
  }
}

TEST(JerkLimited, GreatCircleArcOnTheSphereIsTheDoubleS)
{
  for (const LineCase& c : kLineCases)
  {
    Eigen::VectorXd x(3), y(3);
    x << 1, 0, 0;
    y << std::cos(1.0), std::sin(1.0), 0;
    const auto path = line<Sphere>(x, y);
    expectDoubleS<Sphere>(path, bounds(0.0, 0.0, 0.0, c.v, c.a, c.j), doubleS(1.0, c.v, c.a, c.j),
                          "sphere j=" + std::to_string(c.j));
  }
}

TEST(JerkLimited, PolylineIsTheSumOfItsSegmentsDoubleS)
{
  // Velocity corners: the motion stops at each, every segment is a straight line of its own.
  const std::vector<Pose<double>> points{ pose({ 0, 0, 0 }, { 0, 0, 0 }), pose({ 0, 0, 0 }, { 1, 0, 0 }),
                                          pose({ 0, 0, 0 }, { 1, 0.3, 0 }), pose({ 0, 0, 0 }, { 1, 0.3, 2 }) };
  const auto path = std::make_shared<PiecewiseGeodesic<DoubleGeodesicSe3>>(points, std::vector<double>{ 0, 1, 2, 4 });
  const RateBounds b = bounds(0.8, 1.5, 6.0, 1.0, 1.0, 1.0);
  double reference = 0.0;
  for (double length : { 1.0, 0.3, 2.0 })
    reference += doubleS(length, 0.8, 1.5, 6.0).duration;
  const auto m = expectJerkLimited<DoubleGeodesicSe3>(path, b, "polyline");
  EXPECT_NEAR(m->profile().duration() / reference, 1.0, 0.01);
  EXPECT_EQ(m->profile().segments.size(), 3u);
}

// ---- Curved paths ---------------------------------------------------------------------

TEST(JerkLimited, CurvedPathsOfBothGeometriesKeepEveryBound)
{
  std::mt19937 rng(7);
  const std::vector<Pose<double>> points = test::randomPolygon(rng, 6, 0.8);
  const std::vector<double> times = unevenTimes(points.size(), rng);
  const RateBounds b = bounds(1.0, 2.0, 5.0, 1.5, 3.0, 8.0);
  {
    const auto path = naturalSpline<DoubleGeodesicSe3>(points, times);
    expectJerkLimited<DoubleGeodesicSe3>(path, b, "double geodesic spline");
  }
  {
    const auto path = naturalSpline<ScrewSe3>(points, times);
    expectJerkLimited<ScrewSe3>(path, b, "screw spline");
  }
  {
    const auto path = std::make_shared<CornerBlendedGeodesic<DoubleGeodesicSe3>>(points, times, 0.3, 1.0);
    expectJerkLimited<DoubleGeodesicSe3>(path, b, "corner blend");
  }
}

TEST(JerkLimited, SphereSplineKeepsEveryBound)
{
  std::mt19937 rng(3);
  std::vector<Eigen::VectorXd> points;
  for (int i = 0; i < 5; ++i)
    points.push_back(test::randomUnitVectorX(rng, 3));
  const std::vector<double> times = unevenTimes(points.size(), rng);
  const auto path = naturalSpline<Sphere>(points, times);
  const RateBounds b = bounds(0.0, 0.0, 0.0, 1.0, 2.0, 4.0);
  expectJerkLimited<Sphere>(path, b, "sphere spline");
}

// The acceleration energy the final check integrates (Simpson's rule on its pieces) against a
// midpoint sum of |a|² over 2·10⁵ equal steps of the timed curve's own kinematics, per channel:
// a spline and a corner blend, in both geometries' worth of channels.
TEST(JerkLimited, AccelerationEnergyIsTheMotionsIntegral)
{
  std::mt19937 rng(17);
  const std::vector<Pose<double>> points = test::randomPolygon(rng, 6, 0.8);
  const std::vector<double> times = unevenTimes(points.size(), rng);
  const RateBounds b = bounds(1.0, 2.0, 10.0, 1.5, 3.0, 15.0);
  const std::shared_ptr<const Curve<DoubleGeodesicSe3>> paths[] = {
    naturalSpline<DoubleGeodesicSe3>(points, times),
    std::make_shared<CornerBlendedGeodesic<DoubleGeodesicSe3>>(points, times, 0.3, 1.0)
  };
  for (const auto& path : paths)
  {
    const auto m = timing::makeJerkLimitedCurve<DoubleGeodesicSe3>(path, b);
    const std::size_t steps = 200000;
    const double t0 = m->startTime(), h = (m->endTime() - t0) / static_cast<double>(steps);
    double linear = 0.0, angular = 0.0;
    for (std::size_t i = 0; i < steps; ++i)
    {
      const Kinematics k = kinematicsAt(*m, t0 + (static_cast<double>(i) + 0.5) * h);
      linear += h * k.acceleration.linear.squaredNorm();
      angular += h * k.acceleration.angular.squaredNorm();
    }
    EXPECT_GT(linear, 0.0);
    EXPECT_GT(angular, 0.0);
    EXPECT_NEAR(m->profile().acceleration_energy[timing::kLinear], linear, 1e-4 * linear);
    EXPECT_NEAR(m->profile().acceleration_energy[timing::kAngular], angular, 1e-4 * angular);
  }
}

TEST(JerkLimited, ALooseJerkBoundCostsAtMostThreePercent)
{
  std::mt19937 rng(11);
  const std::vector<Pose<double>> points = test::randomPolygon(rng, 6, 0.8);
  const std::vector<double> times = unevenTimes(points.size(), rng);
  // a / j = 1 ms in both channels.
  const RateBounds b = bounds(1.0, 2.0, 2000.0, 1.5, 3.0, 3000.0);
  const std::shared_ptr<const Curve<DoubleGeodesicSe3>> paths[] = {
    naturalSpline<DoubleGeodesicSe3>(points, times),
    std::make_shared<CornerBlendedGeodesic<DoubleGeodesicSe3>>(points, times, 0.3, 1.0)
  };
  for (const auto& path : paths)
  {
    const double optimum = timeOptimalDuration<DoubleGeodesicSe3>(path, b);
    const auto m = timing::makeJerkLimitedCurve<DoubleGeodesicSe3>(path, b);
    EXPECT_GE(m->profile().duration(), optimum);
    EXPECT_LE(m->profile().duration(), 1.03 * optimum) << "stretch " << m->profile().stretch;
    RecordProperty(path == paths[0] ? "loose_jerk_ratio_spline" : "loose_jerk_ratio_blend",
                   std::to_string(m->profile().duration() / optimum));
    expectWithinBounds(*m, b, "loose jerk");
  }
}

namespace
{
/// The rates along a circle of radius R of a motion with arc speed v, tangential acceleration a_t
/// and its derivative ȧ_t: |a| = |(a_t, v²/R)|, jerk (ȧ_t − v³/R², 3 v a_t / R) (Frenet: Ṫ = (v/R) N,
/// Ṅ = −(v/R) T).
struct CircleRates
{
  double speed, acceleration, jerk;
};

CircleRates circleRates(double R, double v, double at, double jt)
{
  return { v, std::hypot(at, v * v / R), std::hypot(jt - v * v * v / (R * R), 3.0 * v * at / R) };
}

/// The rest-to-rest double S of doubleS as a motion: its arc speed, acceleration
/// and jerk at time t, by integrating its seven constant-jerk phases.
struct DoubleSMotion
{
  double tj, ta, tv, j;
  double duration() const { return 2.0 * ta + tv; }
  /// (v, a, j) at t.
  std::array<double, 3> at(double t) const
  {
    // Phase times and jerks: +j, 0, −j (acceleration), 0 (cruise), −j, 0, +j.
    const double d[7] = { tj, ta - 2.0 * tj, tj, tv, tj, ta - 2.0 * tj, tj };
    const double jerk[7] = { j, 0.0, -j, 0.0, -j, 0.0, j };
    double v = 0.0, a = 0.0;
    for (int k = 0; k < 7; ++k)
    {
      const double h = std::min(t, d[k]);
      v += a * h + 0.5 * jerk[k] * h * h;
      a += jerk[k] * h;
      t -= h;
      if (t <= 0.0)
        return { v, a, jerk[k] };
    }
    return { v, a, 0.0 };
  }
};

/// The double S with limits (v, a, j) over L as a motion (doubleS's phases).
DoubleSMotion doubleSMotion(double L, double v, double a, double j)
{
  double tj, ta;
  if (v * j >= a * a)
  {
    tj = a / j;
    ta = tj + v / a;
  }
  else
  {
    tj = std::sqrt(v / j);
    ta = 2.0 * tj;
  }
  double tv = L / v - ta;
  if (tv < 0.0)
  {
    tv = 0.0;
    tj = a / j;
    ta = 0.5 * (tj + std::sqrt(tj * tj + 4.0 * L / a));
    if (ta < 2.0 * tj)
    {
      tj = std::cbrt(L / (2.0 * j));
      ta = 2.0 * tj;
    }
  }
  return { tj, ta, tv, j };
}
}  // namespace

TEST(JerkLimited, CircleArcIsNearTheBestOfABruteForceFamily)
{
  // p on a circle of radius 1 about the z axis, turning about z: the screw geodesic of a pure
  // rotation about the axis through the origin. Angle 2 rad, arc length 2 m.
  const double R = 1.0, angle = 2.0;
  const auto path = line<ScrewSe3>(pose({ 0, 0, 0 }, { R, 0, 0 }),
                                   pose({ 0, 0, angle }, { R * std::cos(angle), R * std::sin(angle), 0 }));
  const double v = 1.0, a = 1.5, j = 3.0;
  const RateBounds b = bounds(v, a, j, 10.0, 10.0, 100.0);
  // The family: double S along the arc with limits (λ_v v, λ_a a, λ_j j), λ on a grid; feasible
  // when its rates along the circle hold (checked at 4000 instants), the fastest one is kept.
  double best = std::numeric_limits<double>::infinity();
  const int steps = 24;
  for (int iv = 1; iv <= steps; ++iv)
    for (int ia = 1; ia <= steps; ++ia)
      for (int ij = 1; ij <= steps; ++ij)
      {
        const DoubleSMotion m = doubleSMotion(R * angle, v * iv / steps, a * ia / steps, j * ij / steps);
        if (!(m.duration() < best))
          continue;
        bool feasible = true;
        for (int k = 0; k <= 4000 && feasible; ++k)
        {
          const auto s = m.at(m.duration() * k / 4000.0);
          const CircleRates r = circleRates(R, s[0], s[1], s[2]);
          feasible = r.speed <= v * (1 + 1e-9) && r.acceleration <= a * (1 + 1e-9) && r.jerk <= j * (1 + 1e-9);
        }
        if (feasible)
          best = m.duration();
      }
  ASSERT_TRUE(std::isfinite(best));
  const auto motion = timing::makeJerkLimitedCurve<ScrewSe3>(path, b);
  const double d = motion->profile().duration();
  RecordProperty("circle_ratio_to_brute_force", std::to_string(d / best));
  EXPECT_LE(d, 1.05 * best) << d << " s against the family's best " << best << " s";
  EXPECT_GE(d, timeOptimalDuration<ScrewSe3>(path, b));
  expectWithinBounds(*motion, b, "circle arc");
}

// ---- Hard cases -----------------------------------------------------------------------

/// Curved clamped splines at rest at both ends, in both geometries, with the demo's bounds: within
/// every bound, and within 25 % of the acceleration-only optimum (a clamped screw spline through
/// the demo's five poses took 1943 s against 7.3 s before the cap; 7.9 s after).
TEST(JerkLimited, ClampedSplinesAtRestCostLittleMoreThanWithoutJerkBounds)
{
  std::mt19937 rng(11);
  const std::vector<Pose<double>> points = test::randomPolygon(rng, 5, 0.8);
  const std::vector<double> times = unevenTimes(points.size(), rng);
  const RateBounds b = bounds(0.5, 1.0, 10.0, 1.0, 2.0, 20.0);
  {
    using G = DoubleGeodesicSe3;
    const G::Tangent<double> zero = G::log(points[0], points[0]);
    const auto path = makeInterpolatingSpline<G>(points, times, EndCondition::kClamped, zero, zero, zero);
    const auto m = expectJerkLimited<G>(path, b, "clamped double geodesic spline");
    EXPECT_LT(m->profile().duration(), 1.25 * timeOptimalDuration<G>(path, b));
  }
  {
    using G = ScrewSe3;
    const G::Tangent<double> zero = G::log(points[0], points[0]);
    const auto path = makeInterpolatingSpline<G>(points, times, EndCondition::kClamped, zero, zero, zero);
    const auto m = expectJerkLimited<G>(path, b, "clamped screw spline");
    EXPECT_LT(m->profile().duration(), 1.25 * timeOptimalDuration<G>(path, b));
  }
}

TEST(JerkLimited, TinyJerkBoundsOnACurvedPath)
{
  std::mt19937 rng(5);
  const std::vector<Pose<double>> points = test::randomPolygon(rng, 5, 0.8);
  const std::vector<double> times = unevenTimes(points.size(), rng);
  const auto path = naturalSpline<DoubleGeodesicSe3>(points, times);
  const RateBounds b = bounds(1.0, 2.0, 1e-3, 1.5, 3.0, 2e-3);
  expectJerkLimited<DoubleGeodesicSe3>(path, b, "tiny jerk");
}

TEST(JerkLimited, UnevenWaypointTimes)
{
  std::mt19937 rng(9);
  const std::vector<Pose<double>> points = test::randomPolygon(rng, 6, 0.5);
  // Consecutive intervals in ratios up to 10³.
  const std::vector<double> times{ 0.0, 1.0, 1.001, 2.001, 2.002, 3.0 };
  const RateBounds b = bounds(1.0, 2.0, 5.0, 1.5, 3.0, 8.0);
  const auto path = naturalSpline<DoubleGeodesicSe3>(points, times);
  expectJerkLimited<DoubleGeodesicSe3>(path, b, "uneven times");
}

TEST(JerkLimited, AC1PathStopsAtItsJoints)
{
  std::mt19937 rng(13);
  const std::vector<Pose<double>> points = test::randomPolygon(rng, 4, 0.6);
  const std::vector<double> times{ 0.0, 1.0, 2.0, 3.0 };
  // Hermite: C¹ (given velocities), C″ jumps at the inner waypoints.
  std::vector<Vector6<double>> tangents;
  for (std::size_t i = 0; i < points.size(); ++i)
    tangents.push_back(Vector6<double>::Constant(0.3));
  const auto path = std::make_shared<HermiteSpline<DoubleGeodesicSe3>>(points, times, tangents);
  const RateBounds b = bounds(1.0, 2.0, 5.0, 1.5, 3.0, 8.0);
  const auto m = timing::makeJerkLimitedCurve<DoubleGeodesicSe3>(path, b);
  const auto& p = m->profile();
  ASSERT_EQ(p.segments.size(), 3u);
  for (std::size_t k = 1; k < p.segments.size(); ++k)
  {
    EXPECT_EQ(p.base.s[p.segments[k].first], times[k]);
    const double t = p.t0 + (p.segments[k].start - p.t0) * p.stretch;
    for (Side side : { Side::kLeft, Side::kRight })
      for (double r : ratesOf(*m, t, side))
        EXPECT_LE(r, 1e-9) << "joint " << k;
  }
  expectWithinBounds(*m, b, "hermite");
  // A C² path through the same points does not stop.
  const auto smooth = timing::makeJerkLimitedCurve<DoubleGeodesicSe3>(naturalSpline<DoubleGeodesicSe3>(points, times), b);
  EXPECT_EQ(smooth->profile().segments.size(), 1u);
}

TEST(JerkLimited, BadJerkBoundsAreRefusedNamingTheField)
{
  const auto path = line<DoubleGeodesicSe3>(pose({ 0, 0, 0 }, { 0, 0, 0 }), pose({ 0, 0, 1 }, { 1, 0, 0 }));
  for (double bad : { -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity() })
    for (int c = 0; c < 2; ++c)
    {
      RateBounds b = bounds(1, 1, 1, 1, 1, 1);
      b.jerk[c] = bad;
      try
      {
        timing::makeJerkLimitedCurve<DoubleGeodesicSe3>(path, b);
        ADD_FAILURE() << "accepted " << bad;
      }
      catch (const InvalidInputError& e)
      {
        EXPECT_EQ(std::string(e.what()).rfind(c == 0 ? "max_linear_jerk: " : "max_angular_jerk: ", 0), 0u) << e.what();
      }
    }
}

TEST(JerkLimited, WithoutJerkBoundsTheResultIsTimeOptimalsExactly)
{
  const auto path = randomSpline(17, 5, 0.8);
  const RateBounds b = bounds(1.0, 2.0, 0.0, 1.5, 3.0, 0.0);
  const auto reference = timing::makeTimeOptimalCurve<DoubleGeodesicSe3>(path, b);
  const auto m = timing::makeJerkLimitedCurve<DoubleGeodesicSe3>(path, b);
  const auto& p = m->profile().base;
  const auto& q = reference->profile();
  EXPECT_TRUE(m->profile().segments.empty());
  EXPECT_EQ(p.s, q.s);
  EXPECT_EQ(p.t, q.t);
  EXPECT_EQ(p.x, q.x);
  EXPECT_EQ(p.u, q.u);
  EXPECT_EQ(p.stretch, q.stretch);
  for (int i = 0; i <= 100; ++i)
  {
    const double t = q.t.front() + q.duration() * i / 100.0;
    EXPECT_EQ(m->value(t).p, reference->value(t).p);
  }
}

TEST(JerkLimited, StartsFromAMovingStateWithZeroAcceleration)
{
  const auto path = randomSpline(19, 5, 0.6);
  const RateBounds b = bounds(1.0, 2.0, 5.0, 1.5, 3.0, 8.0);
  // Half the speed the bounds allow at the start, then a small path acceleration too.
  const Kinematics k0 = kinematicsAt(*path, path->startTime());
  const double speed = 0.5 / std::max(k0.velocity.linear.norm() / 1.0, k0.velocity.angular.norm() / 1.5);
  for (double acceleration : { 0.0, 0.05 })
  {
    timing::JerkLimitedOptions o;
    o.start_speed = speed;
    o.start_acceleration = acceleration;
    const auto m = timing::makeJerkLimitedCurve<DoubleGeodesicSe3>(path, b, o);
    const Kinematics k = kinematicsAt(*m, m->startTime());
    EXPECT_LE((k.velocity.linear - k0.velocity.linear * speed).norm(), 1e-9);
    EXPECT_LE((k.velocity.angular - k0.velocity.angular * speed).norm(), 1e-9);
    const Eigen::Vector3d a = k0.acceleration.linear * speed * speed + k0.velocity.linear * acceleration;
    EXPECT_LE((k.acceleration.linear - a).norm(), 1e-7);
    EXPECT_EQ(m->profile().stretch, 1.0);
    expectWithinBounds(*m, b, "moving start");
  }
}

TEST(JerkLimited, TimeAtInvertsThePathParameter)
{
  const RateBounds b = bounds(1.0, 2.0, 5.0, 1.5, 3.0, 8.0);
  const auto path = randomSpline(31, 5, 0.8);
  for (const auto& m : { timing::makeJerkLimitedCurve<DoubleGeodesicSe3>(path, b),
                         timing::makeJerkLimitedCurve<DoubleGeodesicSe3>(path, bounds(1, 2, 0, 1.5, 3, 0)) })
  {
    const auto& p = m->profile();
    for (int i = 0; i <= 200; ++i)
    {
      const double t = m->startTime() + (m->endTime() - m->startTime()) * i / 200.0;
      const double s = p.pathParameter(t, Side::kRight);
      // Where the motion rests (its ends) any time of the rest maps back: compare path parameters.
      EXPECT_NEAR(p.pathParameter(p.timeAt(s), Side::kRight), s, 1e-9) << t;
      if (i > 0 && i < 200)
      {
        EXPECT_NEAR(p.timeAt(s), t, 1e-6) << t;
      }
    }
    EXPECT_EQ(p.timeAt(path->startTime()), m->startTime());
    EXPECT_NEAR(p.timeAt(path->endTime()), m->endTime(), 1e-9);
  }
}

TEST(JerkLimited, ReportedFiguresAreThoseOfTheTimedMotion)
{
  const auto path = randomSpline(23, 5, 0.8);
  const RateBounds b = bounds(1.0, 2.0, 5.0, 1.5, 3.0, 8.0);
  const auto m = timing::makeJerkLimitedCurve<DoubleGeodesicSe3>(path, b);
  const auto& p = m->profile();
  // The peaks by dense sampling (the jerk as the finite difference of the accelerations): at most
  // the figures, and close to them.
  std::array<double, 6> sampled{};
  const std::size_t n = 100000;
  const double dt = (m->endTime() - m->startTime()) / n;
  Eigen::VectorXd previous = accelerationOf(*m, m->startTime());
  for (std::size_t i = 0; i <= n; ++i)
  {
    const double t = m->startTime() + dt * static_cast<double>(i);
    const std::array<double, 2> v = channelNorms(velocityOf(*m, t));
    const Eigen::VectorXd a = accelerationOf(*m, t);
    const std::array<double, 2> an = channelNorms(a), jn = channelNorms((a - previous) / dt);
    previous = a;
    for (int c = 0; c < 2; ++c)
    {
      sampled[c] = std::max(sampled[c], v[c]);
      sampled[2 + c] = std::max(sampled[2 + c], an[c]);
      if (i > 0)
        sampled[4 + c] = std::max(sampled[4 + c], jn[c]);
    }
  }
  const std::array<double, 6> reported{ p.max_speed[0],        p.max_speed[1], p.max_acceleration[0],
                                        p.max_acceleration[1], p.max_jerk[0],  p.max_jerk[1] };
  for (int q = 0; q < 6; ++q)
  {
    EXPECT_LE(sampled[q], reported[q] * (1.0 + 1e-6)) << q;
    EXPECT_GE(sampled[q], reported[q] * (1.0 - 1e-2)) << q;
  }
}
