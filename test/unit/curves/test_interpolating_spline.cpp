// curves/interpolating_spline.h: the C² spline through the waypoints (natural / clamped / start)
// in every geometry, and the failures of its solve. Every property is checked against something
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
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/geometry/geometry.h"
#include "spline_test_utils.h"
#include "test_utils.h"

using namespace se3_interpolation;
using namespace se3_interpolation::test;

template <class G>
class Se3Interpolation : public ::testing::Test
{
};
TYPED_TEST_SUITE(Se3Interpolation, Se3Geometries);

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

// ---- failures of the solve -------------------------------------------------------------------

// fuzz_curves finding (now the corpus seed screw_start_overflow): on the screw geometry, start
// data of 3.5e30 rad/s grow quadratically from segment to segment (chart velocities 9e60, 1e90,
// 2e149); the data stayed finite, but se3Exp's cubic terms overflowed and the curve evaluated to
// NaN. The construction now refuses chart excursions beyond kMaxStartChartExcursion, naming the
// waypoint.
TEST(InterpolatingErrors, StartDataThatOverflowTheChartAreRefusedNotEvaluatedToNaN)
{
  auto q = [](double x, double y, double z, double w) { return Quaternion<double>(w, x, y, z).normalized(); };
  const std::vector<Pose<double>> x{
    Pose<double>(q(0, 0, 0, 1), Eigen::Vector3d(0, 0, 0)),
    Pose<double>(q(0.049643371727140964, 0, 0, 0.99203990708293766), Eigen::Vector3d(-8, 6.5625, 6.5625)),
    Pose<double>(q(0.35272653217485861, 0.35272653217485861, -0.86669947905822409, 0),
                 Eigen::Vector3d(-5.375, -5.375, -5.375)),
    Pose<double>(q(0.57017786497743972, 0.57017786497743972, 0.15713563208039677, 0.57017786497743972),
                 Eigen::Vector3d(-8, -6.25, 0)),
  };
  const std::vector<double> t{ 0.0, 1.01545, 2.45453, 3.0 };
  Twist v0;
  v0.linear = Eigen::Vector3d(2.1875, -0.8125, 3.5295369653413445e30);
  v0.angular = Eigen::Vector3d(3.5295369653413445e30, 3.5295369653413445e30, 3.5245852051841973e30);
  try
  {
    const auto c = spline<ScrewSe3>(x, t, EndCondition::kStart, v0);
    for (double s = 0.0; s <= 3.0; s += 0.01)
      ASSERT_TRUE(c->value(s).p.allFinite()) << "a NaN position at t = " << s;
    FAIL() << "expected ConvergenceError";
  }
  catch (const ConvergenceError& e)
  {
    EXPECT_NE(std::string(e.what()).find("the velocity carried to waypoints[1]"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("leave double range"), std::string::npos) << e.what();
  }
  // Moderate start data on the same waypoints still give the C^2 spline through them.
  Twist moderate;
  moderate.angular = Eigen::Vector3d(0.3, -0.2, 0.1);
  const auto c = spline<ScrewSe3>(x, t, EndCondition::kStart, moderate);
  for (std::size_t i = 0; i < x.size(); ++i)
    EXPECT_LT(poseDistance(c->value(t[i]), x[i]), 1e-9);
}

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
    const SphereKinematics l = kinematicsAt(*c, d.t[1], Side::kLeft);
    const SphereKinematics r = kinematicsAt(*c, d.t[1], Side::kRight);
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
    const SphereKinematics l = kinematicsAt(*c, d.t[1], Side::kLeft);
    const SphereKinematics r = kinematicsAt(*c, d.t[1], Side::kRight);
    EXPECT_LT((l.velocity - r.velocity).norm(), 1e-9 * velocity_scale);
    EXPECT_LT((l.acceleration - r.acceleration).norm(), 1e-9 * acceleration_scale);
    EXPECT_LT((l.acceleration - left.tail(3)).norm(), 2e-2 * acceleration_scale);
  }
}

namespace
{
/// The jump of the stacked ambient state (velocity, covariant acceleration) of a sphere curve
/// at t, relative to 1 + the size of both sides: the measure of fuzz_c2's continuity check.
double relativeStateJump(const Curve<Sphere>& c, double t)
{
  const SphereKinematics l = kinematicsAt(c, t, Side::kLeft);
  const SphereKinematics r = kinematicsAt(c, t, Side::kRight);
  Eigen::VectorXd left(2 * l.velocity.size()), right(2 * r.velocity.size());
  left << l.velocity, l.acceleration;
  right << r.velocity, r.acceleration;
  return (left - right).norm() / (1.0 + left.norm() + right.norm());
}
}  // namespace

// Found by fuzz_c2 (fuzz_c2-sphere-s2-acceleration-jump and -s4-, now seeds of
// test/fuzz/corpus_c2; decoded with fuzz_c2.cpp's reader): natural splines on S^2 and S^4 whose
// first step is pi - 1e-6 rad in 2.5e-6 s (S^2) and 2.25e-5 s (S^4), beyond
// kMinSphereConjugateGap, then a step of about 1.9 and 2.1 rad in 0.625 and 1.5 s. The solved
// curve passed the check on the scale of its terms (6 pi/h^2 = 3e12), yet its acceleration at
// waypoints[1] jumped by 43 on 6e6 (S^2; 7e-6 of the state) and by 0.67 on 2.7e5 (S^4;
// 2.5e-6): the terms' rounding, amplified by the condition of D_0 (~1/gap), swamps the value.
// verifyContinuity now asks the state's own continuity too (kStateContinuityTolerance), so
// these are refused naming waypoints[1].
TEST(OtherGeometries, SphereSplinesWhoseStateJumpsByRoundingAreRefused)
{
  auto vector = [](std::initializer_list<double> v) {
    Eigen::VectorXd x(static_cast<Eigen::Index>(v.size()));
    Eigen::Index i = 0;
    for (double c : v)
      x[i++] = c;
    return x;
  };
  const std::vector<std::pair<std::vector<Eigen::VectorXd>, std::vector<double>>> findings{
    { { vector({ 0.57573739305282234, 0.56652559476397724, -0.58955509048609012 }),
        vector({ -0.57573697282587422, -0.5665251812606602, 0.5895558982139647 }),
        vector({ 0.17055801024859291, -0.96907960368518697, -0.1783106470780744 }) },
      { -1.125, -1.1249975000000001, -0.49999750000000009 } },
    { { vector({ -0.67808839075063865, 0.085428458677245814, -0.67808839075063865, 0.042714229338622907,
                 -0.26696393336639318 }),
        vector({ 0.67808912573066304, -0.08542837986142926, 0.67808776515009472, -0.04271418993071463,
                 0.26696368706696644 }),
        vector({ -0.52950046096879844, -0.22692876898662792, -0.15816247535431643, 0.79768900613481331,
                 -0.082519552358773784 }) },
      { -1.6875, -1.6874775, -0.18747749999999996 } },
  };
  for (const auto& finding : findings)
  {
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(finding.first[0].size());
    std::string what;
    try
    {
      const auto c = solveC2Spline<Sphere>(finding.first, finding.second, EndCondition::kNatural, zero, zero);
      ADD_FAILURE() << "returned, with a relative state jump of " << relativeStateJump(*c, finding.second[1])
                    << " at waypoints[1]";
      continue;
    }
    catch (const ConvergenceError& e)
    {
      what = e.what();
    }
    EXPECT_NE(what.find("the solved spline is not C^2 at waypoints[1]"), std::string::npos) << what;
    EXPECT_NE(what.find("of the state"), std::string::npos) << what;
  }
}

// Every near-antipodal spline the solve returns is C^2 by fuzz_c2's measure: 400 random
// configurations of the findings' shape on S^2 ... S^4 (a first step pi - gap, gap from 1e-8 to
// 1e-2 rad, in h from 1e-6 to 1 s; a second step to a random point after 1e-3 ... 10 s), both
// end conditions. Either refused (a ConvergenceError) or continuous to 1e-6 of the state.
TEST(OtherGeometries, NearAntipodalSplinesAreRefusedOrC2ByTheStateMeasure)
{
  std::mt19937 rng(1500);
  std::uniform_real_distribution<double> exponent(0.0, 1.0);
  int solved = 0, refused = 0;
  for (int k = 0; k < 400; ++k)
  {
    const int dim = 3 + k % 3;
    const Eigen::VectorXd x0 = test::randomUnitVectorX(rng, dim);
    const Eigen::MatrixXd b = TangentFrame<Sphere>::basis(x0);
    const Eigen::VectorXd u = b * test::randomUnitVectorX(rng, dim - 1);
    const double gap = std::pow(10.0, -8.0 + 6.0 * exponent(rng));
    const double h0 = std::pow(10.0, -6.0 + 6.0 * exponent(rng));
    const double h1 = std::pow(10.0, -3.0 + 4.0 * exponent(rng));
    const double a = M_PI - gap;
    const std::vector<Eigen::VectorXd> x{ x0, Eigen::VectorXd(std::cos(a) * x0 + std::sin(a) * u),
                                          test::randomUnitVectorX(rng, dim) };
    const std::vector<double> t{ 0.0, h0, h0 + h1 };
    const EndCondition condition = k % 2 == 0 ? EndCondition::kNatural : EndCondition::kClamped;
    const Eigen::VectorXd v0 = b * test::randomUnitVectorX(rng, dim - 1);
    Eigen::VectorXd v1 = test::randomUnitVectorX(rng, dim);
    v1 -= v1.dot(x[2]) * x[2];
    try
    {
      const auto c = solveC2Spline<Sphere>(x, t, condition, v0, v1);
      ++solved;
      EXPECT_LT(relativeStateJump(*c, t[1]), 1e-6) << "gap " << gap << " h0 " << h0 << " h1 " << h1;
    }
    catch (const ConvergenceError&)
    {
      ++refused;
    }
  }
  // most are solved: the refusal is for rounding, not for the shape
  EXPECT_GT(solved, 300) << refused << " refused";
}
