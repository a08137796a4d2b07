// curves/chart_cubic.h: the transition derivatives of the chart cubics against the right Jacobian
// and finite differences of the chart; the closed-form kinematics of a double-geodesic chart cubic,
// and the rates alone that the time-optimal timing's path jets take, against its second-order jets.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>
#include <tuple>

#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/curves/chart_cubic.h"
#include "se3_interpolation/timing/jerk_limited.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "spline_test_utils.h"
#include "test_utils.h"

using namespace se3_interpolation;
using namespace se3_interpolation::test;

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

TEST(ChartCubic, ClosedFormKinematicsAreTheSecondOrderJetsOnes)
{
  // ChartCubicSpline<DoubleGeodesicSe3>::kinematics (DoubleGeodesicSe3::expKinematics) against
  // kinematicsFromJet of the same spline's second-order jet, which evaluates exp in Taylor
  // arithmetic: every piece, both sides of every breakpoint and random interior times; segment
  // rotations of angle 0, 1e-9, 1e-4, at the series switch (0.2), 1, 3 and π − 1e-9; end rates from
  // 0 to large (chart vectors beyond π inside a segment); times with ratios up to 10³.
  std::mt19937 rng(2026);
  const std::vector<double> angles{ 0.0, 1e-9, 1e-4, 0.2, 1.0, 3.0, 3.14159265358979323846 - 1e-9 };
  for (int trial = 0; trial < 6; ++trial)
  {
    const std::size_t n = angles.size() + 1;
    std::vector<Pose<double>> points{ test::randomPose(rng) };
    std::vector<double> times{ 0.0 };
    std::vector<Vector6<double>> logs, starts, ends;
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
      const double angle = angles[(i + static_cast<std::size_t>(trial)) % angles.size()];
      points.push_back(points.back() *
                       Pose<double>(so3Exp<double>(Eigen::Vector3d(angle * test::randomUnitVector<3>(rng))),
                                    Eigen::Vector3d(test::randomUnitVector<3>(rng))));
      times.push_back(times.back() + std::pow(10.0, std::uniform_real_distribution<double>(-1.5, 1.5)(rng)));
      logs.push_back(DoubleGeodesicSe3::log(points[i], points[i + 1]));
      const double scale = trial == 0 ? 0.0 : 0.5 * trial;
      const Twist s = randomTwist(rng, scale), e = randomTwist(rng, scale);
      starts.push_back((Vector6<double>() << s.angular, s.linear).finished());
      ends.push_back((Vector6<double>() << e.angular, e.linear).finished());
    }
    const ChartCubicSpline<DoubleGeodesicSe3> spline(points, times, logs, starts, ends);
    std::vector<std::pair<double, Side>> at;
    for (std::size_t i = 0; i < n; ++i)
      for (Side side : { Side::kLeft, Side::kRight })
        at.emplace_back(times[i], side);
    for (int k = 0; k < 40; ++k)
      at.emplace_back(std::uniform_real_distribution<double>(times.front(), times.back())(rng), Side::kRight);
    for (const auto& [t, side] : at)
    {
      const Kinematics closed = spline.kinematics(t, side);
      const Kinematics jets = kinematicsFromJet(spline.jet(Jet<2>::variable(t), side));
      const auto near = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
        return (a - b).norm() <= 1e-12 * (1.0 + b.norm());
      };
      EXPECT_TRUE(near(closed.velocity.linear, jets.velocity.linear)) << "t = " << t;
      EXPECT_TRUE(near(closed.acceleration.linear, jets.acceleration.linear)) << "t = " << t;
      EXPECT_TRUE(near(closed.velocity.angular, jets.velocity.angular))
          << "t = " << t << ": " << closed.velocity.angular.transpose() << " vs " << jets.velocity.angular.transpose();
      EXPECT_TRUE(near(closed.acceleration.angular, jets.acceleration.angular))
          << "t = " << t << ": " << closed.acceleration.angular.transpose() << " vs "
          << jets.acceleration.angular.transpose();
      EXPECT_TRUE(near(closed.pose.p, jets.pose.p)) << "t = " << t;
      EXPECT_LT(closed.pose.q.angularDistance(jets.pose.q), 1e-12) << "t = " << t;
      // kinematicsAt takes the closed form for this curve.
      const Kinematics dispatched = kinematicsAt<DoubleGeodesicSe3>(spline, t, side);
      EXPECT_EQ(dispatched.acceleration.angular, closed.acceleration.angular);
      // The rates alone (the angular parts in the segment start's frame) have the jets' norms and
      // inner products within each part, and so do the time-optimal timing's path jets, which
      // take them.
      const MotionRates rates = spline.rates(t, side);
      const auto same = [](double a, double b) { return std::abs(a - b) <= 1e-12 * (1.0 + std::abs(b)); };
      for (const auto& [r, j] : { std::pair<const Twist*, const Twist*>{ &rates.velocity, &jets.velocity },
                                  { &rates.acceleration, &jets.acceleration } })
      {
        EXPECT_TRUE(same(r->linear.norm(), j->linear.norm())) << "t = " << t;
        EXPECT_TRUE(same(r->angular.norm(), j->angular.norm())) << "t = " << t;
      }
      EXPECT_TRUE(same(rates.velocity.angular.dot(rates.acceleration.angular),
                       jets.velocity.angular.dot(jets.acceleration.angular)))
          << "t = " << t;
      EXPECT_TRUE(same(rates.velocity.linear.dot(rates.acceleration.linear),
                       jets.velocity.linear.dot(jets.acceleration.linear)))
          << "t = " << t;
      const timing::PathJet path = timing::CurvePath<DoubleGeodesicSe3>(
                                       std::shared_ptr<const Curve<DoubleGeodesicSe3>>(&spline, [](const auto*) {}))
                                       .jet(t, side);
      const timing::PathJet reference = timing::pathJet(jets.velocity, jets.acceleration);
      for (int c = 0; c < 2; ++c)
      {
        EXPECT_TRUE(same(path[c].bb, reference[c].bb)) << "t = " << t << " channel " << c;
        EXPECT_TRUE(same(path[c].ab, reference[c].ab)) << "t = " << t << " channel " << c;
        EXPECT_TRUE(same(path[c].aa, reference[c].aa)) << "t = " << t << " channel " << c;
      }
      // With the jerk: rates3 (DoubleGeodesicSe3::expRates3) against the third-order jet's
      // kinematics, exp in Taylor arithmetic: the first two rates are rates()'s, the linear jerk
      // the same vector, the angular jerk's norm and its products with the angular velocity and
      // acceleration the jets' (its frame is the segment start's); the jerk-limited timing's path
      // jets, which take them, agree.
      const MotionRates3 rates3 = spline.rates3(t, side);
      const timing::Kinematics3 jets3 = timing::kinematics3FromJet(spline.jet3(Jet<3>::variable(t), side));
      EXPECT_EQ(rates3.velocity.angular, rates.velocity.angular);
      EXPECT_EQ(rates3.acceleration.angular, rates.acceleration.angular);
      EXPECT_EQ(rates3.acceleration.linear, rates.acceleration.linear);
      EXPECT_TRUE(near(rates3.jerk.linear, jets3.jerk.linear)) << "t = " << t;
      EXPECT_TRUE(same(rates3.jerk.angular.norm(), jets3.jerk.angular.norm()))
          << "t = " << t << ": " << rates3.jerk.angular.norm() << " vs " << jets3.jerk.angular.norm();
      EXPECT_TRUE(same(rates3.jerk.angular.dot(rates3.velocity.angular),
                       jets3.jerk.angular.dot(jets3.velocity.angular)))
          << "t = " << t;
      EXPECT_TRUE(same(rates3.jerk.angular.dot(rates3.acceleration.angular),
                       jets3.jerk.angular.dot(jets3.acceleration.angular)))
          << "t = " << t;
      const timing::PathJet3 path3 = timing::CurveJerkPath<DoubleGeodesicSe3>(
                                         std::shared_ptr<const Curve<DoubleGeodesicSe3>>(&spline, [](const auto*) {}))
                                         .jet3(t, side);
      const timing::PathJet3 reference3 = timing::pathJet3(jets3);
      for (int c = 0; c < 2; ++c)
        for (const auto& [name, mine, theirs] :
             { std::tuple<const char*, double, double>{ "bc", path3[c].bc, reference3[c].bc },
               { "ac", path3[c].ac, reference3[c].ac },
               { "cc", path3[c].cc, reference3[c].cc },
               { "aa", path3[c].aa, reference3[c].aa } })
          EXPECT_TRUE(same(mine, theirs)) << "t = " << t << " channel " << c << " " << name << ": " << mine << " vs "
                                          << theirs;
    }
  }
}
