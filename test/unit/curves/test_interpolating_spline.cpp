// Interpolating curves: the C² spline through the waypoints (natural / clamped / start), Hermite
// cubics, the twist conversions they use, the banded solver, and their use by the planner
// (timing, stretching to bounds, errors). Every property is checked against something
// computed independently here: classical splines by their own tridiagonal solve, spatial
// derivatives by kinematicsAt (quaternion differentiation) and central differences.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/math/banded_lu.h"
#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/curves/hermite.h"
#include "se3_interpolation/curves/interpolating_spline.h"
#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/analysis/sphere_kinematics.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/geometry/se3_velocity.h"
#include "test_utils.h"

using namespace se3_interpolation;
using test::poseDistance;
using test::randomPolygon;
using test::randomPose;

namespace
{
// ---- Independent references ------------------------------------------------------------

/// The classical cubic spline through y_i at t_i in second-derivative form: M_i = S''(t_i) from
/// h_{i−1} M_{i−1} + 2(h_{i−1} + h_i) M_i + h_i M_{i+1} = 6 (Δ_i/h_i − Δ_{i−1}/h_{i−1}), with
/// M_0 = M_{N−1} = 0 (natural) or the end-slope rows (clamped); solved by the Thomas algorithm.
class ClassicalSpline
{
public:
  ClassicalSpline(std::vector<double> t, std::vector<Eigen::VectorXd> y, bool clamped = false,
                  const Eigen::VectorXd& v0 = Eigen::VectorXd(), const Eigen::VectorXd& v1 = Eigen::VectorXd())
    : t_(std::move(t)), y_(std::move(y))
  {
    const std::size_t n = t_.size();
    const Eigen::Index dim = y_[0].size();
    std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 0.0);
    std::vector<Eigen::VectorXd> r(n, Eigen::VectorXd::Zero(dim));
    auto h = [&](std::size_t i) { return t_[i + 1] - t_[i]; };
    auto slope = [&](std::size_t i) -> Eigen::VectorXd { return (y_[i + 1] - y_[i]) / h(i); };
    for (std::size_t i = 1; i + 1 < n; ++i)
    {
      a[i] = h(i - 1);
      b[i] = 2.0 * (h(i - 1) + h(i));
      c[i] = h(i);
      r[i] = 6.0 * (slope(i) - slope(i - 1));
    }
    if (clamped)
    {
      b[0] = 2.0 * h(0);
      c[0] = h(0);
      r[0] = 6.0 * (slope(0) - v0);
      a[n - 1] = h(n - 2);
      b[n - 1] = 2.0 * h(n - 2);
      r[n - 1] = 6.0 * (v1 - slope(n - 2));
    }
    for (std::size_t i = 1; i < n; ++i)
    {
      const double w = a[i] / b[i - 1];
      b[i] -= w * c[i - 1];
      r[i] -= w * r[i - 1];
    }
    m_.assign(n, Eigen::VectorXd());
    m_[n - 1] = r[n - 1] / b[n - 1];
    for (std::size_t i = n - 1; i-- > 0;)
      m_[i] = (r[i] - c[i] * m_[i + 1]) / b[i];
  }

  Eigen::VectorXd operator()(double s) const
  {
    std::size_t i = 0;
    while (i + 2 < t_.size() && s > t_[i + 1])
      ++i;
    const double h = t_[i + 1] - t_[i];
    const double l = t_[i + 1] - s;
    const double r = s - t_[i];
    return m_[i] * (l * l * l / (6.0 * h)) + m_[i + 1] * (r * r * r / (6.0 * h)) +
           (y_[i] / h - m_[i] * (h / 6.0)) * l + (y_[i + 1] / h - m_[i + 1] * (h / 6.0)) * r;
  }

private:
  std::vector<double> t_;
  std::vector<Eigen::VectorXd> y_;
  std::vector<Eigen::VectorXd> m_;
};

/// Classical cubic Hermite interpolation.
Eigen::VectorXd classicalHermite(const std::vector<double>& t, const std::vector<Eigen::VectorXd>& y,
                                 const std::vector<Eigen::VectorXd>& v, double s)
{
  std::size_t i = 0;
  while (i + 2 < t.size() && s > t[i + 1])
    ++i;
  const double h = t[i + 1] - t[i];
  const double u = (s - t[i]) / h;
  const double h00 = 2 * u * u * u - 3 * u * u + 1, h10 = u * u * u - 2 * u * u + u;
  const double h01 = -2 * u * u * u + 3 * u * u, h11 = u * u * u - u * u;
  return h00 * y[i] + h10 * h * v[i] + h01 * y[i + 1] + h11 * h * v[i + 1];
}

/// Classical forward cubic spline from p(t_0), p'(t_0), p''(t_0): on each segment the cubic
/// p(t_i + s) = x_i + v s + a s²/2 + c s³ through x_{i+1}, its end slope and curvature carried on.
Eigen::VectorXd classicalForward(const std::vector<double>& t, const std::vector<Eigen::VectorXd>& y,
                                 Eigen::VectorXd v, Eigen::VectorXd a, double s)
{
  for (std::size_t i = 0; i + 1 < t.size(); ++i)
  {
    const double h = t[i + 1] - t[i];
    const Eigen::VectorXd c = (y[i + 1] - y[i] - v * h - a * (h * h / 2.0)) / (h * h * h);
    if (s <= t[i + 1] || i + 2 == t.size())
    {
      const double r = s - t[i];
      return y[i] + v * r + a * (r * r / 2.0) + c * (r * r * r);
    }
    v = v + a * h + c * (3.0 * h * h);
    a = a + c * (6.0 * h);
  }
  return y.back();
}

// ---- Data --------------------------------------------------------------------------------

std::vector<double> randomTimes(std::mt19937& rng, std::size_t n)
{
  std::uniform_real_distribution<double> step(0.5, 1.5);
  std::vector<double> t{ 0.3 };
  for (std::size_t i = 1; i < n; ++i)
    t.push_back(t.back() + step(rng));
  return t;
}

Twist randomTwist(std::mt19937& rng, double scale)
{
  std::normal_distribution<double> n(0.0, scale);
  Twist v;
  v.linear = Eigen::Vector3d(n(rng), n(rng), n(rng));
  v.angular = Eigen::Vector3d(n(rng), n(rng), n(rng));
  return v;
}

double relativeError(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  return (a - b).norm() / std::max(1.0, b.norm());
}

double twistError(const Twist& a, const Twist& b)
{
  return std::max(relativeError(a.linear, b.linear), relativeError(a.angular, b.angular));
}

Vector6<double> zero6()
{
  return Vector6<double>::Zero();
}

template <class G>
std::shared_ptr<const Curve<G>> spline(const std::vector<Pose<double>>& x, const std::vector<double>& t, EndCondition c,
                                       const Twist& v0 = Twist(), const Twist& v1 = Twist(), const Twist& a0 = Twist())
{
  return makeInterpolatingSpline<G>(x, t, c, velocityToTangent<G>(x.front(), v0), velocityToTangent<G>(x.back(), v1),
                                    accelerationToTangent<G>(x.front(), v0, a0));
}

template <class G>
class Se3Interpolation : public ::testing::Test
{
};
using Se3Geometries = ::testing::Types<ScrewSe3, DoubleGeodesicSe3>;
TYPED_TEST_SUITE(Se3Interpolation, Se3Geometries);

/// The spatial kinematics of the motion t ↦ G::exp(x, t v + t² a/2) at t = 0, by kinematics.h.
template <class G>
Kinematics kinematicsOfExpCurve(const Pose<double>& x, const Vector6<double>& v, const Vector6<double>& a)
{
  Vector6<Jet<2>> y;
  for (int k = 0; k < 6; ++k)
  {
    y[k] = Jet<2>(0.0);
    y[k].coefficient(1) = v[k];
    y[k].coefficient(2) = a[k] / 2.0;
  }
  return kinematicsFromJet(G::exp(x.cast<Jet<2>>(), y));
}
}  // namespace

// ---- se3_velocity.h ----------------------------------------------------------------------

TYPED_TEST(Se3Interpolation, TangentsOfExponentialMotionsMatchTheirSpatialKinematics)
{
  // (T1), (T2): along y(s) = s v + s² a/2 in the chart at x the velocity is v and the
  // acceleration a; kinematics.h differentiates the quaternion and position directly.
  std::mt19937 rng(100);
  for (int i = 0; i < 200; ++i)
  {
    const Pose<double> x = randomPose(rng);
    Vector6<double> v, a;
    for (int k = 0; k < 6; ++k)
    {
      v[k] = std::normal_distribution<double>(0.0, 1.0)(rng);
      a[k] = std::normal_distribution<double>(0.0, 1.0)(rng);
    }
    const Kinematics k = kinematicsOfExpCurve<TypeParam>(x, v, a);
    EXPECT_LT(twistError(tangentToVelocity<TypeParam>(x, v), k.velocity), 1e-13);
    EXPECT_LT(twistError(tangentToAcceleration<TypeParam>(x, k.velocity, a), k.acceleration), 1e-13);
    EXPECT_LT((velocityToTangent<TypeParam>(x, k.velocity) - v).norm(), 1e-13 * (1.0 + v.norm()));
    EXPECT_LT((accelerationToTangent<TypeParam>(x, k.velocity, k.acceleration) - a).norm(), 1e-13 * (1.0 + a.norm()));
  }
}

TYPED_TEST(Se3Interpolation, TangentConversionsMatchFiniteDifferencesOfTheChart)
{
  // A generic motion (not a chart polynomial): spatial derivatives by central differences of
  // poses, chart derivatives y'(0), y''(0) of y(s) = log(g(t), g(t + s)) by central differences.
  std::mt19937 rng(101);
  for (int i = 0; i < 50; ++i)
  {
    const Pose<double> x0 = randomPose(rng);
    Vector6<double> xi1, xi2;
    xi1 << test::randomUnitVector<3>(rng), 2.0 * test::randomUnitVector<3>(rng);
    xi2 << 0.7 * test::randomUnitVector<3>(rng), test::randomUnitVector<3>(rng);
    const Eigen::Vector3d w3 = 0.5 * test::randomUnitVector<3>(rng);
    auto g = [&](double t) {
      return x0 * se3Exp<double>(Vector6<double>(t * xi1 + t * t * xi2)) *
             Pose<double>(so3Exp<double>(Eigen::Vector3d(t * t * t * w3)), Eigen::Vector3d(t * t, -t, 0.5 * t * t * t));
    };
    const double t = 0.4;
    const double h = 1e-3;
    const Kinematics k = test::centralDifferences(g, t, h);
    const Pose<double> c = g(t);
    auto y = [&](double s) { return TypeParam::log(c, g(t + s)); };
    const Vector6<double> dy = (-y(2 * h) + 8.0 * y(h) - 8.0 * y(-h) + y(-2 * h)) / (12.0 * h);
    const Vector6<double> ddy = (-y(2 * h) + 16.0 * y(h) + 16.0 * y(-h) - y(-2 * h)) / (12.0 * h * h);
    EXPECT_LT((velocityToTangent<TypeParam>(c, k.velocity) - dy).norm(), 1e-8);
    EXPECT_LT((accelerationToTangent<TypeParam>(c, k.velocity, k.acceleration) - ddy).norm(), 1e-5);
  }
}

TEST(TangentMotion, ScrewAccelerationIsTheRateOfTheBodyTwist)
{
  // (T2) for the screw metric = d/dt (Rᵀω, Rᵀṗ), the body twist differentiated numerically.
  std::mt19937 rng(102);
  const std::vector<Pose<double>> x = randomPolygon(rng, 4);
  const BezierCurve<ScrewSe3> c(x, 0.0, 2.0);
  auto body = [&](double t) {
    const Kinematics k = kinematicsAt(c, t);
    return velocityToTangent<ScrewSe3>(k.pose, k.velocity);
  };
  for (double t : { 0.3, 1.1, 1.8 })
  {
    const double h = 1e-4;
    const Vector6<double> rate = (body(t + h) - body(t - h)) / (2.0 * h);
    EXPECT_LT((tangentMotion<ScrewSe3>(c, t).acceleration - rate).norm(), 1e-6 * (1.0 + rate.norm()));
  }
}

TEST(ChartCubic, TransitionDerivativesAreTheRightJacobianAndTheSecondDerivativeOfTheChart)
{
  // (C3) of chart_cubic.h: on SO(3), D = dF(0) for F(δ) = Log(Exp(-L) Exp(L + δ)) is the right
  // Jacobian J_r(L) = I - (1 - cos θ)/θ² [L]x + (θ - sin θ)/θ³ [L]x² (closed form), and Q(w) =
  // d²/ds² F(s w) at 0, here by central differences of F itself; random L up to 3 rad.
  std::mt19937 rng(103);
  for (int i = 0; i < 20; ++i)
  {
    const Quaternion<double> q0 = so3Exp<double>(Eigen::Vector3d(test::randomUnitVector<3>(rng)));
    const Eigen::Vector3d l = std::uniform_real_distribution<double>(0.1, 3.0)(rng) * test::randomUnitVector<3>(rng);
    const Quaternion<double> q1 = q0 * so3Exp<double>(l);
    const Eigen::Vector3d log = So3::log(q0, q1);
    const TransitionDerivatives d =
        transitionDerivatives<So3>(q0, q1, log, Eigen::Matrix3d::Identity(), Eigen::Matrix3d::Identity());
    const double theta = l.norm();
    const Eigen::Matrix3d k = hat<double>(l);
    const Eigen::Matrix3d jr = Eigen::Matrix3d::Identity() - (1.0 - std::cos(theta)) / (theta * theta) * k +
                               (theta - std::sin(theta)) / (theta * theta * theta) * k * k;
    EXPECT_LT((d.jacobian - jr).norm(), 1e-13);
    const Eigen::Vector3d w = 2.0 * test::randomUnitVector<3>(rng);
    auto f = [&](double s) {
      return Eigen::Vector3d(So3::log(q1, Quaternion<double>(q0 * so3Exp<double>(Eigen::Vector3d(log + s * w)))));
    };
    const double e = 1e-3;
    const Eigen::Vector3d second = (-f(2 * e) + 16.0 * f(e) - 30.0 * f(0.0) + 16.0 * f(-e) - f(-2 * e)) / (12 * e * e);
    EXPECT_LT((d.quadraticForm(w) - second).norm(), 1e-6 * (1.0 + second.norm()));
    // Its derivative 2 Q(w, .) against differences of the quadratic form.
    const Eigen::Vector3d u = test::randomUnitVector<3>(rng);
    const Eigen::Vector3d dq = (d.quadraticForm(w + 1e-4 * u) - d.quadraticForm(w - 1e-4 * u)) / 2e-4;
    EXPECT_LT((d.quadraticJacobian(w) * u - dq).norm(), 1e-8 * (1.0 + dq.norm()));
  }
}

// ---- banded_lu.h --------------------------------------------------------------------------

TEST(BandedLu, MatchesDenseLuWithPivoting)
{
  std::mt19937 rng(110);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial)
  {
    const Eigen::Index size = 30 + trial, lower = 1 + trial % 4, upper = 2 + trial % 3;
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(size, size);
    BandedLu banded(size, lower, upper);
    for (Eigen::Index r = 0; r < size; ++r)
      for (Eigen::Index c = std::max<Eigen::Index>(0, r - lower); c <= std::min(size - 1, r + upper); ++c)
      {
        // Zero diagonal every third row: elimination without row interchanges would fail.
        const double value = (r == c && r % 3 == 0) ? 0.0 : n(rng);
        dense(r, c) = value;
        banded(r, c) = value;
      }
    const Eigen::VectorXd b = Eigen::VectorXd::Random(size);
    banded.factorize();
    const Eigen::VectorXd x = banded.solve(b);
    const Eigen::VectorXd ref = dense.partialPivLu().solve(b);
    EXPECT_LT((x - ref).norm(), 1e-9 * (1.0 + ref.norm()));
    EXPECT_LT((dense * x - b).norm(), 1e-10 * (1.0 + b.norm()));
  }
}

TEST(BandedLu, SingularMatrixThrows)
{
  BandedLu banded(4, 1, 1);
  banded(0, 0) = 1.0;
  banded(1, 1) = 2.0;
  banded(3, 3) = 1.0;  // row and column 2 empty
  EXPECT_THROW(banded.factorize(), ConvergenceError);
}

// ---- interpolating: natural / clamped ------------------------------------------------------

TYPED_TEST(Se3Interpolation, PassesEveryWaypointAndIsC2)
{
  std::mt19937 rng(120);
  for (std::size_t n : { 3u, 10u, 50u })
    for (EndCondition condition : { EndCondition::kNatural, EndCondition::kClamped })
    {
      const std::vector<Pose<double>> x = randomPolygon(rng, n);
      const std::vector<double> t = randomTimes(rng, n);
      const Twist v0 = randomTwist(rng, 0.5), v1 = randomTwist(rng, 0.5);
      const auto c = spline<TypeParam>(x, t, condition, v0, v1);
      ASSERT_EQ(c->breakpoints(), t);
      EXPECT_EQ(c->controlPoints().size(), 3 * n - 2);
      for (std::size_t i = 0; i < n; ++i)
      {
        EXPECT_LT(poseDistance(c->value(t[i]), x[i]), 1e-10) << "n " << n << " waypoint " << i;
        EXPECT_LT(poseDistance(kinematicsAt(*c, t[i], Side::kLeft).pose, x[i]), 1e-10);
      }
      for (std::size_t i = 1; i + 1 < n; ++i)
      {
        const Kinematics l = kinematicsAt(*c, t[i], Side::kLeft);
        const Kinematics r = kinematicsAt(*c, t[i], Side::kRight);
        EXPECT_LT(twistError(l.velocity, r.velocity), 1e-8) << "n " << n << " knot " << i;
        EXPECT_LT(twistError(l.acceleration, r.acceleration), 1e-8) << "n " << n << " knot " << i;
        // Central differences across the knot: O(h²) for velocities, O(h · jump of the jerk)
        // for accelerations (the curve is only C² there).
        const Kinematics f = test::centralDifferences([&](double s) { return c->value(s); }, t[i], 1e-4);
        EXPECT_LT(twistError(f.velocity, r.velocity), 1e-6);
        EXPECT_LT(twistError(f.acceleration, r.acceleration), 1e-3);
      }
    }
}

TYPED_TEST(Se3Interpolation, NaturalEndsHaveZeroGeodesicAcceleration)
{
  // (S2) in spatial terms, (A1)/(A2) derived by hand: ω̇ = 0 at both ends, and p̈ = 0 for the
  // double geodesic, p̈ = ω × ṗ (constant body twist) for the screw.
  std::mt19937 rng(121);
  const bool screw = std::is_same<TypeParam, ScrewSe3>::value;
  for (int trial = 0; trial < 5; ++trial)
  {
    const std::size_t n = 4 + 3 * static_cast<std::size_t>(trial);
    const std::vector<Pose<double>> x = randomPolygon(rng, n);
    const std::vector<double> t = randomTimes(rng, n);
    const auto c = spline<TypeParam>(x, t, EndCondition::kNatural);
    for (const Kinematics& k :
         { kinematicsAt(*c, t.front(), Side::kRight), kinematicsAt(*c, t.back(), Side::kLeft) })
    {
      const Eigen::Vector3d linear =
          screw ? Eigen::Vector3d(k.acceleration.linear - k.velocity.angular.cross(k.velocity.linear)) :
                  k.acceleration.linear;
      const double scale = 1.0 + k.velocity.linear.norm() + k.velocity.angular.norm();
      EXPECT_LT(k.acceleration.angular.norm(), 1e-9 * scale);
      EXPECT_LT(linear.norm(), 1e-9 * scale);
    }
  }
}

TYPED_TEST(Se3Interpolation, ClampedEndsHaveTheGivenVelocities)
{
  std::mt19937 rng(122);
  for (std::size_t n : { 2u, 3u, 8u })
  {
    const std::vector<Pose<double>> x = randomPolygon(rng, n);
    const std::vector<double> t = randomTimes(rng, n);
    const Twist v0 = randomTwist(rng, 1.0), v1 = randomTwist(rng, 1.0);
    const auto c = spline<TypeParam>(x, t, EndCondition::kClamped, v0, v1);
    EXPECT_LT(twistError(kinematicsAt(*c, t.front(), Side::kRight).velocity, v0), 1e-10);
    EXPECT_LT(twistError(kinematicsAt(*c, t.back(), Side::kLeft).velocity, v1), 1e-10);
  }
}

TYPED_TEST(Se3Interpolation, PureTranslationsFollowTheClassicalSpline)
{
  std::mt19937 rng(123);
  std::normal_distribution<double> nd(0.0, 2.0);
  for (bool clamped : { false, true })
    for (std::size_t n : { 2u, 3u, 7u, 20u })
    {
      const std::vector<double> t = randomTimes(rng, n);
      std::vector<Pose<double>> x;
      std::vector<Eigen::VectorXd> y;
      for (std::size_t i = 0; i < n; ++i)
      {
        y.push_back(Eigen::Vector3d(nd(rng), nd(rng), nd(rng)));
        x.emplace_back(Quaternion<double>::Identity(), y.back());
      }
      Twist v0, v1;
      v0.linear = Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
      v1.linear = Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
      const auto c = spline<TypeParam>(x, t, clamped ? EndCondition::kClamped : EndCondition::kNatural, v0, v1);
      const ClassicalSpline ref(t, y, clamped, v0.linear, v1.linear);
      for (int s = 0; s <= 200; ++s)
      {
        const double time = t.front() + (t.back() - t.front()) * s / 200.0;
        const Pose<double> g = c->value(time);
        EXPECT_LT((g.p - ref(time)).norm(), 1e-10) << "clamped " << clamped << " n " << n << " t " << time;
        EXPECT_LT(rotationAngle(g.q), 1e-12);
      }
    }
}

TYPED_TEST(Se3Interpolation, RotationsAboutOneAxisFollowTheClassicalSplineInTheAngle)
{
  std::mt19937 rng(124);
  const Eigen::Vector3d axis = test::randomUnitVector<3>(rng);
  // More than a full turn in total; every step below π.
  const std::vector<double> angles{ 0.2, 1.3, 2.9, 4.0, 5.5, 6.1, 8.0 };
  const std::vector<double> t = randomTimes(rng, angles.size());
  std::vector<Pose<double>> x;
  std::vector<Eigen::VectorXd> y;
  for (double a : angles)
  {
    x.emplace_back(so3Exp<double>(a * axis), Eigen::Vector3d::Zero());
    y.push_back(Eigen::VectorXd::Constant(1, a));
  }
  Twist v0, v1;
  v0.angular = 0.7 * axis;
  v1.angular = -1.2 * axis;
  for (bool clamped : { false, true })
  {
    const auto c = spline<TypeParam>(x, t, clamped ? EndCondition::kClamped : EndCondition::kNatural, v0, v1);
    const ClassicalSpline ref(t, y, clamped, Eigen::VectorXd::Constant(1, 0.7), Eigen::VectorXd::Constant(1, -1.2));
    for (int s = 0; s <= 200; ++s)
    {
      const double time = t.front() + (t.back() - t.front()) * s / 200.0;
      const Pose<double> expected(so3Exp<double>(ref(time)[0] * axis), Eigen::Vector3d::Zero());
      EXPECT_LT(poseDistance(c->value(time), expected), 1e-10) << "clamped " << clamped << " t " << time;
    }
  }
}

TYPED_TEST(Se3Interpolation, GeodesicBSplineIsOnlyC1)
{
  // Why `interpolating` is not built as a geodesic B-spline (interpolating_spline.h): the
  // generalised de Boor algorithm joins its pieces with equal velocities, but on a curved group
  // not with equal accelerations. In R³ (pure translations) it is the classical C² B-spline.
  std::mt19937 rng(127);
  double smallest_jump = 1e9;
  double largest_jump = 0.0;
  for (int trial = 0; trial < 10; ++trial)
  {
    const std::vector<Pose<double>> d = randomPolygon(rng, 8, 1.0);
    const BSplineCurve<TypeParam> c(d, 3, clampedUniformKnots(8, 3, 0.0, 5.0));
    std::vector<Pose<double>> translated;
    for (const auto& p : d)
      translated.emplace_back(Quaternion<double>::Identity(), p.p);
    const BSplineCurve<TypeParam> flat(translated, 3, clampedUniformKnots(8, 3, 0.0, 5.0));
    for (double knot : { 1.0, 2.0, 3.0, 4.0 })
    {
      const Kinematics l = kinematicsAt(c, knot, Side::kLeft), r = kinematicsAt(c, knot, Side::kRight);
      EXPECT_LT(twistError(l.velocity, r.velocity), 1e-12);
      smallest_jump = std::min(smallest_jump, twistError(l.acceleration, r.acceleration));
      largest_jump = std::max(largest_jump, twistError(l.acceleration, r.acceleration));
      EXPECT_LT(twistError(kinematicsAt(flat, knot, Side::kLeft).acceleration,
                           kinematicsAt(flat, knot, Side::kRight).acceleration),
                1e-12);
    }
  }
  EXPECT_GT(smallest_jump, 1e-9);  // far above rounding at every knot
  EXPECT_GT(largest_jump, 1e-4);
}

TYPED_TEST(Se3Interpolation, TwoWaypointsNaturalIsTheGeodesic)
{
  std::mt19937 rng(125);
  for (int trial = 0; trial < 10; ++trial)
  {
    const std::vector<Pose<double>> x = randomPolygon(rng, 2, 2.5);
    const std::vector<double> t{ 1.0, 3.5 };
    const auto c = spline<TypeParam>(x, t, EndCondition::kNatural);
    for (double s : { 0.0, 0.2, 0.5, 0.9, 1.0 })
      EXPECT_LT(poseDistance(c->value(1.0 + 2.5 * s), geodesic<TypeParam>(x[0], x[1], s)), 1e-10);
  }
}

// Linear growth of the solve is measured by bench/bench_interpolating.cpp (no wall-clock
// assertions in tests); here: 10^4 waypoints are solved and interpolated exactly.
TYPED_TEST(Se3Interpolation, TenThousandWaypoints)
{
  std::mt19937 rng(126);
  const std::size_t n = 10000;
  const std::vector<Pose<double>> x = randomPolygon(rng, n);
  const std::vector<double> t = randomTimes(rng, n);
  const auto c = spline<TypeParam>(x, t, EndCondition::kNatural);
  double worst = 0.0;
  for (std::size_t k = 0; k < n; ++k)
    worst = std::max(worst, poseDistance(c->value(t[k]), x[k]));
  EXPECT_LT(worst, 1e-10);
}

// ---- interpolating in the other geometries -----------------------------------------------

TEST(OtherGeometries, EuclideanEqualsTheClassicalSpline)
{
  std::mt19937 rng(130);
  std::normal_distribution<double> nd(0.0, 1.0);
  const std::size_t n = 12;
  const std::vector<double> t = randomTimes(rng, n);
  std::vector<Eigen::VectorXd> y;
  for (std::size_t i = 0; i < n; ++i)
    y.push_back(Eigen::Vector2d(nd(rng), nd(rng)));
  const Eigen::VectorXd v0 = Eigen::Vector2d(1.0, -2.0), v1 = Eigen::Vector2d(0.5, 0.3);
  for (bool clamped : { false, true })
  {
    const auto c = makeInterpolatingSpline<Euclidean>(y, t, clamped ? EndCondition::kClamped : EndCondition::kNatural,
                                                      v0, v1, Eigen::VectorXd::Zero(2));
    const ClassicalSpline ref(t, y, clamped, v0, v1);
    for (int s = 0; s <= 100; ++s)
    {
      const double time = t.front() + (t.back() - t.front()) * s / 100.0;
      EXPECT_LT((c->value(time) - ref(time)).norm(), 1e-11);
    }
  }
}

TEST(OtherGeometries, So3NaturalSplineInterpolatesWithZeroEndAngularAcceleration)
{
  std::mt19937 rng(131);
  const std::size_t n = 15;
  std::vector<Quaternion<double>> q{ so3Exp<double>(test::randomUnitVector<3>(rng)) };
  for (std::size_t i = 1; i < n; ++i)
    q.push_back(q.back() * so3Exp<double>(1.2 * test::randomUnitVector<3>(rng)));
  const std::vector<double> t = randomTimes(rng, n);
  const auto c = makeInterpolatingSpline<So3>(q, t, EndCondition::kNatural, Eigen::Vector3d::Zero(),
                                              Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  auto kin = [&](double time, Side side) {
    return kinematicsFromJet(Pose<Jet<2>>(c->jet(Jet<2>::variable(time), side), Vector3<Jet<2>>::Zero()));
  };
  for (std::size_t i = 0; i < n; ++i)
    EXPECT_LT(rotationAngle(Quaternion<double>(q[i].conjugate() * c->value(t[i]))), 1e-12);
  for (std::size_t i = 1; i + 1 < n; ++i)
  {
    EXPECT_LT(twistError(kin(t[i], Side::kLeft).velocity, kin(t[i], Side::kRight).velocity), 1e-9);
    EXPECT_LT(twistError(kin(t[i], Side::kLeft).acceleration, kin(t[i], Side::kRight).acceleration), 1e-9);
  }
  EXPECT_LT(kin(t.front(), Side::kRight).acceleration.angular.norm(), 1e-10);
  EXPECT_LT(kin(t.back(), Side::kLeft).acceleration.angular.norm(), 1e-10);
}

TEST(OtherGeometries, SphereSplinesInterpolateAreC2AndMeetTheirEndConditions)
{
  // Checked in ambient coordinates: C² means equal ambient first and second derivatives; the
  // natural end condition is a vanishing covariant acceleration c̈ − (c̈·c) c.
  std::mt19937 rng(132);
  for (int m : { 2, 3 })
  {
    const std::size_t n = 12;
    std::vector<Eigen::VectorXd> x{ test::randomUnitVectorX(rng, m + 1) };
    for (std::size_t i = 1; i < n; ++i)
    {
      const Eigen::MatrixXd b = TangentFrame<Sphere>::basis(x.back());
      x.push_back(Sphere::exp(x.back(), Eigen::VectorXd(b * test::randomUnitVectorX(rng, m) * 0.9)));
    }
    const std::vector<double> t = randomTimes(rng, n);
    const Eigen::MatrixXd b0 = TangentFrame<Sphere>::basis(x.front());
    const Eigen::MatrixXd b1 = TangentFrame<Sphere>::basis(x.back());
    const Eigen::VectorXd v0 = b0 * test::randomUnitVectorX(rng, m);
    const Eigen::VectorXd v1 = b1 * test::randomUnitVectorX(rng, m) * 0.5;
    for (EndCondition condition : { EndCondition::kNatural, EndCondition::kClamped })
    {
      const auto c = makeInterpolatingSpline<Sphere>(x, t, condition, v0, v1, Eigen::VectorXd::Zero(m + 1));
      auto ambient = [&](double time, Side side, int k) -> Eigen::VectorXd {
        return jetCoefficients(c->jet(Jet<2>::variable(time), side), k) * (k == 2 ? 2.0 : 1.0);
      };
      for (std::size_t i = 0; i < n; ++i)
        EXPECT_LT((c->value(t[i]) - x[i]).norm(), 1e-11) << "m " << m << " waypoint " << i;
      for (std::size_t i = 1; i + 1 < n; ++i)
        for (int k : { 1, 2 })
          EXPECT_LT((ambient(t[i], Side::kLeft, k) - ambient(t[i], Side::kRight, k)).norm(),
                    1e-8 * (1.0 + ambient(t[i], Side::kRight, k).norm()));
      for (int end = 0; end < 2; ++end)
      {
        const double time = end == 0 ? t.front() : t.back();
        const Side side = end == 0 ? Side::kRight : Side::kLeft;
        const Eigen::VectorXd p = end == 0 ? x.front() : x.back();
        const Eigen::VectorXd acc = ambient(time, side, 2);
        if (condition == EndCondition::kNatural)
        {
          EXPECT_LT((acc - acc.dot(p) * p).norm(), 1e-9 * (1.0 + acc.norm()));
        }
        else
        {
          EXPECT_LT((ambient(time, side, 1) - (end == 0 ? v0 : v1)).norm(), 1e-10);
        }
      }
    }
  }
}

TEST(OtherGeometries, SphereRejectsANonTangentVelocity)
{
  std::vector<Eigen::VectorXd> x{ Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1) };
  const Eigen::VectorXd normal = Eigen::Vector3d(1, 0, 0);
  const Eigen::VectorXd zero = Eigen::Vector3d::Zero();
  try
  {
    makeInterpolatingSpline<Sphere>(x, { 0.0, 1.0, 2.0 }, EndCondition::kClamped, normal, zero, zero);
    FAIL() << "expected InvalidInputError";
  }
  catch (const InvalidInputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("start_velocity"), std::string::npos) << e.what();
  }
}

// ---- interpolating: start (Algorithm 7.4.1 / Case 2) ----------------------------------------

TYPED_TEST(Se3Interpolation, StartSplineMatchesItsStartDataAndIsC2)
{
  std::mt19937 rng(140);
  for (int trial = 0; trial < 5; ++trial)
  {
    // Waypoints along a smooth motion (about 2 rad in all), start data near the motion's own.
    const Pose<double> x0 = randomPose(rng);
    Vector6<double> xi1, xi2;
    xi1 << 0.6 * test::randomUnitVector<3>(rng), test::randomUnitVector<3>(rng);
    xi2 << 0.2 * test::randomUnitVector<3>(rng), 0.3 * test::randomUnitVector<3>(rng);
    const std::size_t n = 5;
    const std::vector<double> t = randomTimes(rng, n);
    auto motion = [&](double s) {
      const double tau = 2.0 * (s - t.front()) / (t.back() - t.front());
      return x0 * se3Exp<double>(Vector6<double>(tau * xi1 + tau * tau * xi2));
    };
    std::vector<Pose<double>> x;
    for (double s : t)
      x.push_back(motion(s));
    const Kinematics own = test::centralDifferences(motion, t.front(), 1e-4);
    Twist v0 = own.velocity, a0 = own.acceleration;
    const Twist dv = randomTwist(rng, 0.01), da = randomTwist(rng, 0.01);
    v0.linear += dv.linear;
    v0.angular += dv.angular;
    a0.linear += da.linear;
    a0.angular += da.angular;
    const auto c = spline<TypeParam>(x, t, EndCondition::kStart, v0, Twist(), a0);
    const Kinematics k0 = kinematicsAt(*c, t.front(), Side::kRight);
    EXPECT_LT(twistError(k0.velocity, v0), 1e-10);
    EXPECT_LT(twistError(k0.acceleration, a0), 1e-9);
    for (std::size_t i = 0; i < n; ++i)
      EXPECT_LT(poseDistance(c->value(t[i]), x[i]), 1e-10);
    for (std::size_t i = 1; i + 1 < n; ++i)
    {
      const Kinematics l = kinematicsAt(*c, t[i], Side::kLeft);
      const Kinematics r = kinematicsAt(*c, t[i], Side::kRight);
      EXPECT_LT(twistError(l.velocity, r.velocity), 1e-8) << "knot " << i;
      EXPECT_LT(twistError(l.acceleration, r.acceleration), 1e-8) << "knot " << i;
    }
  }
}

TYPED_TEST(Se3Interpolation, StartSplineForTranslationsIsTheClassicalForwardSpline)
{
  std::mt19937 rng(141);
  std::normal_distribution<double> nd(0.0, 1.0);
  const std::size_t n = 6;
  const std::vector<double> t = randomTimes(rng, n);
  std::vector<Pose<double>> x;
  std::vector<Eigen::VectorXd> y;
  for (std::size_t i = 0; i < n; ++i)
  {
    y.push_back(Eigen::Vector3d(nd(rng), nd(rng), nd(rng)));
    x.emplace_back(Quaternion<double>::Identity(), y.back());
  }
  Twist v0, a0;
  v0.linear = Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
  a0.linear = Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
  const auto c = spline<TypeParam>(x, t, EndCondition::kStart, v0, Twist(), a0);
  for (int s = 0; s <= 300; ++s)
  {
    const double time = t.front() + (t.back() - t.front()) * s / 300.0;
    const Eigen::VectorXd ref = classicalForward(t, y, v0.linear, a0.linear, time);
    EXPECT_LT((c->value(time).p - ref).norm(), 1e-9 * (1.0 + ref.norm())) << "t " << time;
  }
}

TYPED_TEST(Se3Interpolation, StartSplineIsC2UntilItsGrowingDataLeaveDoubleRange)
{
  // The forward recursion amplifies its data from segment to segment (quadratically in the
  // velocity on a curved group): on random waypoints it stays an exact C² spline while its
  // velocities grow by orders of magnitude, and once they leave double range the error names
  // the waypoint and the cause. (The Crouch Case 1 construction refused at the first control
  // point half a turn away, after a few segments.)
  std::mt19937 rng(142);
  const std::vector<Pose<double>> x = randomPolygon(rng, 40);
  const std::vector<double> t = randomTimes(rng, 40);
  const std::vector<Pose<double>> head(x.begin(), x.begin() + 9);
  const std::vector<double> head_t(t.begin(), t.begin() + 9);
  const auto c = spline<TypeParam>(head, head_t, EndCondition::kStart);
  for (std::size_t i = 0; i < head.size(); ++i)
    EXPECT_LT(poseDistance(c->value(head_t[i]), head[i]), 1e-12);
  for (std::size_t i = 1; i + 1 < head.size(); ++i)
  {
    const Kinematics l = kinematicsAt(*c, head_t[i], Side::kLeft);
    const Kinematics r = kinematicsAt(*c, head_t[i], Side::kRight);
    const double v = std::max(r.velocity.linear.norm(), r.velocity.angular.norm());
    EXPECT_LT(twistError(l.velocity, r.velocity), 1e-9 * (1.0 + v)) << "knot " << i;
    EXPECT_LT((l.acceleration.angular - r.acceleration.angular).norm(), 1e-9 * (1.0 + v * v)) << "knot " << i;
    EXPECT_LT((l.acceleration.linear - r.acceleration.linear).norm(), 1e-9 * (1.0 + v * v)) << "knot " << i;
  }
  EXPECT_GT(kinematicsAt(*c, head_t.back(), Side::kLeft).velocity.angular.norm(), 1e3);
  try
  {
    spline<TypeParam>(x, t, EndCondition::kStart);
    FAIL() << "expected ConvergenceError";
  }
  catch (const ConvergenceError& e)
  {
    EXPECT_NE(std::string(e.what()).find("end_condition 'start'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("leave double range"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("amplifies"), std::string::npos) << e.what();
  }
}

// ---- hermite ---------------------------------------------------------------------------------

TYPED_TEST(Se3Interpolation, HermiteHasTheGivenVelocityAtEveryWaypoint)
{
  std::mt19937 rng(150);
  for (int trial = 0; trial < 10; ++trial)
  {
    const std::size_t n = 2 + static_cast<std::size_t>(trial);
    const std::vector<Pose<double>> x = randomPolygon(rng, n);
    const std::vector<double> t = randomTimes(rng, n);
    std::vector<Twist> velocities;
    std::vector<Vector6<double>> tangents;
    for (std::size_t i = 0; i < n; ++i)
    {
      velocities.push_back(randomTwist(rng, 1.0));
      tangents.push_back(velocityToTangent<TypeParam>(x[i], velocities[i]));
    }
    const HermiteSpline<TypeParam> c(x, t, tangents);
    for (std::size_t i = 0; i < n; ++i)
    {
      EXPECT_LT(poseDistance(c.value(t[i]), x[i]), 1e-12);
      if (i > 0)
      {
        EXPECT_LT(twistError(kinematicsAt(c, t[i], Side::kLeft).velocity, velocities[i]), 1e-10) << i;
      }
      if (i + 1 < n)
      {
        EXPECT_LT(twistError(kinematicsAt(c, t[i], Side::kRight).velocity, velocities[i]), 1e-10) << i;
      }
    }
    EXPECT_EQ(c.controlPoints().size(), 3 * n - 2);
  }
}

TYPED_TEST(Se3Interpolation, HermiteForTranslationsIsTheClassicalHermite)
{
  std::mt19937 rng(151);
  std::normal_distribution<double> nd(0.0, 1.0);
  const std::size_t n = 7;
  const std::vector<double> t = randomTimes(rng, n);
  std::vector<Pose<double>> x;
  std::vector<Eigen::VectorXd> y, v;
  std::vector<Vector6<double>> tangents;
  for (std::size_t i = 0; i < n; ++i)
  {
    y.push_back(Eigen::Vector3d(nd(rng), nd(rng), nd(rng)));
    v.push_back(Eigen::Vector3d(nd(rng), nd(rng), nd(rng)));
    x.emplace_back(Quaternion<double>::Identity(), y.back());
    Twist tw;
    tw.linear = v.back();
    tangents.push_back(velocityToTangent<TypeParam>(x.back(), tw));
  }
  // Estimated velocities (H2), computed here from the positions alone.
  std::vector<Eigen::VectorXd> estimated(n);
  estimated[0] = (y[1] - y[0]) / (t[1] - t[0]);
  estimated[n - 1] = (y[n - 1] - y[n - 2]) / (t[n - 1] - t[n - 2]);
  for (std::size_t i = 1; i + 1 < n; ++i)
  {
    const double hm = t[i] - t[i - 1], hp = t[i + 1] - t[i];
    estimated[i] = (hm * (y[i + 1] - y[i]) / hp + hp * (y[i] - y[i - 1]) / hm) / (hm + hp);
  }
  const HermiteSpline<TypeParam> given(x, t, tangents);
  const HermiteSpline<TypeParam> estimated_curve(x, t, estimateTangents<TypeParam>(x, t));
  for (int s = 0; s <= 300; ++s)
  {
    const double time = t.front() + (t.back() - t.front()) * s / 300.0;
    EXPECT_LT((given.value(time).p - classicalHermite(t, y, v, time)).norm(), 1e-12);
    EXPECT_LT((estimated_curve.value(time).p - classicalHermite(t, y, estimated, time)).norm(), 1e-12);
    EXPECT_LT(rotationAngle(given.value(time).q), 1e-14);
  }
}

TEST(Hermite, EstimatedVelocitiesAreExactForQuadraticMotion)
{
  // (H2) differentiates the quadratic through three neighbours: exact for p(t) = a + b t + c t².
  const Eigen::Vector3d a(1, -2, 0.5), b(0.3, 1.1, -0.7), c(-0.4, 0.25, 0.9);
  const std::vector<double> t{ 0.0, 0.4, 1.5, 1.9, 3.2 };
  std::vector<Eigen::VectorXd> x;
  for (double s : t)
    x.push_back(a + b * s + c * s * s);
  const auto v = estimateTangents<Euclidean>(x, t);
  for (std::size_t i = 1; i + 1 < t.size(); ++i)
    EXPECT_LT((v[i] - (b + 2.0 * c * t[i])).norm(), 1e-13);
  EXPECT_LT((v.front() - (x[1] - x[0]) / 0.4).norm(), 1e-14);
}

TEST(Hermite, EstimatedTangentsAreGeodesicForTwoPoints)
{
  std::mt19937 rng(152);
  const std::vector<Pose<double>> x = randomPolygon(rng, 2, 2.0);
  const std::vector<double> t{ 0.0, 2.0 };
  const HermiteSpline<ScrewSe3> c(x, t, estimateTangents<ScrewSe3>(x, t));
  for (double s : { 0.1, 0.5, 0.8 })
    EXPECT_LT(poseDistance(c.value(2.0 * s), geodesic<ScrewSe3>(x[0], x[1], s)), 1e-12);
}

TEST(Hermite, TooLargeVelocityIsRejectedByName)
{
  std::mt19937 rng(153);
  const std::vector<Pose<double>> x = randomPolygon(rng, 3);
  std::vector<Vector6<double>> v(3, zero6());
  v[1] << 0.0, 0.0, 12.0, 0.0, 0.0, 0.0;  // 12 rad/s: h v/3 = 4 rad on a 1 s segment
  try
  {
    HermiteSpline<DoubleGeodesicSe3>(x, { 0.0, 1.0, 2.0 }, v);
    FAIL() << "expected InvalidInputError";
  }
  catch (const InvalidInputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("velocities[1]"), std::string::npos) << e.what();
  }
}

// ---- failures of the solve -------------------------------------------------------------------

TEST(InterpolatingErrors, IterationLimitThrowsConvergenceError)
{
  std::mt19937 rng(160);
  const std::vector<Pose<double>> x = randomPolygon(rng, 10);
  const std::vector<double> t = randomTimes(rng, 10);
  SplineSolverOptions options;
  options.max_iterations = 1;
  try
  {
    makeInterpolatingSpline<ScrewSe3>(x, t, EndCondition::kNatural, zero6(), zero6(), zero6(), options);
    FAIL() << "expected ConvergenceError";
  }
  catch (const ConvergenceError& e)
  {
    EXPECT_NE(std::string(e.what()).find("did not converge in 1 Newton iterations"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("end_condition 'natural'"), std::string::npos) << e.what();
  }
}

TEST(InterpolatingErrors, NonFiniteWaypointThrowsConvergenceError)
{
  std::mt19937 rng(161);
  std::vector<Pose<double>> x = randomPolygon(rng, 6);
  x[3].p.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(makeInterpolatingSpline<DoubleGeodesicSe3>(x, randomTimes(rng, 6), EndCondition::kNatural, zero6(),
                                                         zero6(), zero6()),
               ConvergenceError);
}

TEST(InterpolatingErrors, BadTimesAndTangentsAreNamed)
{
  std::mt19937 rng(162);
  const std::vector<Pose<double>> x = randomPolygon(rng, 4);
  auto message = [&](const std::function<void()>& f) {
    try
    {
      f();
    }
    catch (const InvalidInputError& e)
    {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([&] {
              makeInterpolatingSpline<ScrewSe3>(x, { 0.0, 1.0, 1.0, 2.0 }, EndCondition::kNatural, zero6(), zero6(),
                                                zero6());
            }).find("times[2]"),
            std::string::npos);
  EXPECT_NE(message([&] {
              makeInterpolatingSpline<ScrewSe3>(x, { 0.0, 1.0, 2.0 }, EndCondition::kNatural, zero6(), zero6(),
                                                zero6());
            }).find("times: 3 given for 4"),
            std::string::npos);
  Vector6<double> nan = zero6();
  nan[4] = std::numeric_limits<double>::infinity();
  EXPECT_NE(message([&] {
              makeInterpolatingSpline<ScrewSe3>(x, { 0.0, 1.0, 2.0, 3.0 }, EndCondition::kClamped, zero6(), nan,
                                                zero6());
            }).find("end_velocity"),
            std::string::npos);
  EXPECT_NE(message([&] {
              HermiteSpline<ScrewSe3>(x, { 0.0, 1.0, 2.0, 3.0 }, std::vector<Vector6<double>>(3, zero6()));
            }).find("velocities: 3 given for 4"),
            std::string::npos);
  const std::vector<Eigen::VectorXd> y{ Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), Eigen::Vector2d(1, 1) };
  EXPECT_NE(message([&] {
              makeInterpolatingSpline<Euclidean>(y, { 0.0, 1.0, 2.0 }, EndCondition::kClamped, Eigen::Vector3d(1, 0, 0),
                                                 Eigen::Vector2d(0, 0), Eigen::Vector2d(0, 0));
            }).find("start_velocity: has 3 components"),
            std::string::npos);
}

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
      const TrajectoryResult out = generate(r, PlannerLimits());
      for (std::size_t i = 0; i < x.size(); ++i)
        EXPECT_LT(poseDistance(out.samples[i].pose, x[i]), 1e-10) << geometry << " " << curve << " " << i;
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
    TrajectoryResult out = generate(r, PlannerLimits());
    EXPECT_LT(twistError(out.samples.front().velocity, r.start_velocity), 1e-9) << geometry;
    EXPECT_LT(twistError(out.samples.back().velocity, r.end_velocity), 1e-9) << geometry;

    r.curve = "hermite";
    r.sample_times = t;
    for (std::size_t i = 0; i < x.size(); ++i)
      r.velocities.push_back(randomTwist(rng, 0.5));
    out = generate(r, PlannerLimits());
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
      const TrajectoryResult out = generate(r, PlannerLimits());
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
      generate(r, PlannerLimits());
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

namespace
{
/// The data of test/fuzz/findings/fuzz_c2-sphere-acceleration-jump (decoded by hand from
/// fuzz_c2.cpp's reader): a natural spline on S^2 through x0, x1 = x0 turned by pi - gap
/// (nearly antipodal) after `h`, and a third point 0.625 later.
struct NearAntipodalData
{
  std::vector<Eigen::VectorXd> x;
  std::vector<double> t;
};

NearAntipodalData nearAntipodal(double gap, double h)
{
  NearAntipodalData d;
  Eigen::VectorXd x0(3), x2(3), u(3);
  x0 << 1.0, 0.0, -3.125;
  x0.normalize();
  u << 0.0, 1.0, 0.0;  // already orthogonal to x0
  x2 << -4.8125, -2.0625, -1.4375;
  x2.normalize();
  const double a = M_PI - gap;
  d.x = { x0, Eigen::VectorXd(std::cos(a) * x0 + std::sin(a) * u), x2 };
  d.t = { -1.125, -1.125 + h, -1.125 + h + 0.625 };
  return d;
}

/// Velocity and covariant acceleration at t from one side, by one-sided second-order finite
/// differences of the curve's values (independent of its jets): the covariant acceleration is
/// the tangential part of the ambient one.
Eigen::VectorXd finiteDifferenceState(const Curve<Sphere>& c, double t, double step, double sign)
{
  const Eigen::VectorXd p0 = c.value(t), p1 = c.value(t + sign * step), p2 = c.value(t + 2.0 * sign * step),
                        p3 = c.value(t + 3.0 * sign * step);
  const Eigen::VectorXd v = sign * (-3.0 * p0 + 4.0 * p1 - p2) / (2.0 * step);
  const Eigen::VectorXd a = (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) / (step * step);
  Eigen::VectorXd s(6);
  s << v, a - p0.dot(a) * p0;
  return s;
}
}  // namespace

// Found by fuzz_c2: x0 -> x1 is pi - 1e-12 rad in 2.5e-6 s, so near the conjugate point of the
// sphere that its transition map D_0 has condition ~3e12. Newton's rows converged, yet the curve's
// acceleration at waypoints[1] was 45351 from the left and -4.5 from the right. Such a step is
// refused (kMinSphereConjugateGap), naming the waypoints.
TEST(OtherGeometries, NearAntipodalShortStepIsRefusedNotReturnedAsC2)
{
  const NearAntipodalData d = nearAntipodal(1e-12, 2.5e-6);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(3);
  try
  {
    solveC2Spline<Sphere>(d.x, d.t, EndCondition::kNatural, zero, zero);
    FAIL() << "a spline that is not C^2 at waypoints[1] was returned";
  }
  catch (const ConvergenceError& e)
  {
    const std::string what = e.what();
    EXPECT_NE(what.find("the step from waypoints[0] to waypoints[1] is "), std::string::npos) << what;
    EXPECT_NE(what.find(" rad from the antipode, closer than 1e-08 rad"), std::string::npos) << what;
  }
}

// Found by fuzz_c2 (fuzz_c2-sphere-ambient-drift, now a seed of test/fuzz/corpus_c2): the same
// shape from another x0, pi - 1.0002e-12 rad in 2.5e-6 s, passed the solver's own continuity
// check (on the scale of its terms, 6 pi/h^2 = 3e12), yet the acceleration at waypoints[1]
// from the ambient jet jumped by 4e-4 on values of 10. Steps within kMinSphereConjugateGap
// (1e-8 rad) of the antipode are refused: there the measured jump reaches 0.15 of the value at
// 1e-10 rad; at 2e-8 rad the two sides agree to 1e-6 of the value.
TEST(OtherGeometries, StepsNearerTheAntipodeThanTheConjugateGapAreRefused)
{
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(3);
  Eigen::VectorXd x0(3), x1(3), x2(3);
  x0 << 0.33871946827274163, 0.0, -0.94088741186872682;
  x1 << -0.33871946827274163, 1.0002113652622558e-12, 0.94088741186872682;
  x2 << -0.87858974062823336, -0.3918035329828608, -0.27307518965472116;
  const std::vector<Eigen::VectorXd> finding{ x0, x1, x2 };
  const std::vector<double> finding_times{ -1.125, -1.1249975000000001, -0.49999750000000009 };
  auto refusal = [&](const std::vector<Eigen::VectorXd>& x, const std::vector<double>& t) {
    try
    {
      solveC2Spline<Sphere>(x, t, EndCondition::kNatural, zero, zero);
    }
    catch (const ConvergenceError& e)
    {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string what = refusal(finding, finding_times);
  EXPECT_NE(what.find("the step from waypoints[0] to waypoints[1] is 1e-12 rad from the antipode, closer than 1e-08"),
            std::string::npos)
      << what;
  for (double gap : { 1e-9, 1e-10, 9.9e-9 })
  {
    const NearAntipodalData d = nearAntipodal(gap, 2.5e-6);
    EXPECT_NE(refusal(d.x, d.t).find("from the antipode"), std::string::npos) << gap;
  }
  for (double h : { 1e-5, 1e-3, 0.1 })
  {
    const NearAntipodalData d = nearAntipodal(2e-8, h);
    const auto c = solveC2Spline<Sphere>(d.x, d.t, EndCondition::kNatural, zero, zero);
    const SphereKinematics l = sphereKinematicsAt(*c, d.t[1], Side::kLeft);
    const SphereKinematics r = sphereKinematicsAt(*c, d.t[1], Side::kRight);
    EXPECT_LT((l.velocity - r.velocity).norm(), 1e-6 * (l.velocity.norm() + r.velocity.norm())) << h;
    EXPECT_LT((l.acceleration - r.acceleration).norm(), 1e-6 * (l.acceleration.norm() + r.acceleration.norm()))
        << h << ": " << l.acceleration.transpose() << " | " << r.acceleration.transpose();
  }
}

// The same shape farther from the antipode, or with a longer step, is still solved, and is C^2
// at waypoints[1] by one-sided finite differences of its values.
TEST(OtherGeometries, NearAntipodalWellConditionedStepsStaySolvedAndC2)
{
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(3);
  for (const auto& gap_h : { std::make_pair(1e-4, 1e-3), std::make_pair(1e-6, 0.1), std::make_pair(1e-4, 1.0) })
  {
    const NearAntipodalData d = nearAntipodal(gap_h.first, gap_h.second);
    const auto c = solveC2Spline<Sphere>(d.x, d.t, EndCondition::kNatural, zero, zero);
    // Step: h/1000 keeps the O(step^2) truncation of both formulas near 1e-5 of the scales
    // pi/h and 6 pi/h^2 (the derivatives above the second scale with 1/h^3, 1/h^4), and the
    // rounding (eps/step, eps/step^2 relative) far below it.
    const double step = gap_h.second / 1000.0;
    const Eigen::VectorXd left = finiteDifferenceState(*c, d.t[1], step, -1.0);
    const Eigen::VectorXd right = finiteDifferenceState(*c, d.t[1], step, 1.0);
    const double h = gap_h.second;
    const double velocity_scale = M_PI / h, acceleration_scale = 6.0 * M_PI / (h * h);
    EXPECT_LT((left.head(3) - right.head(3)).norm(), 1e-3 * velocity_scale) << gap_h.first << " " << h;
    EXPECT_LT((left.tail(3) - right.tail(3)).norm(), 2e-2 * acceleration_scale) << gap_h.first << " " << h;
    // the one-sided jets agree much closer than the differences can tell
    const SphereKinematics l = sphereKinematicsAt(*c, d.t[1], Side::kLeft);
    const SphereKinematics r = sphereKinematicsAt(*c, d.t[1], Side::kRight);
    EXPECT_LT((l.velocity - r.velocity).norm(), 1e-9 * velocity_scale);
    EXPECT_LT((l.acceleration - r.acceleration).norm(), 1e-9 * acceleration_scale);
    EXPECT_LT((l.acceleration - left.tail(3)).norm(), 2e-2 * acceleration_scale);
  }
}
