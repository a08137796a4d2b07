// curves/chart_cubic.h: the transition derivatives of the chart cubics against the right Jacobian
// and finite differences of the chart.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

#include "se3_interpolation/curves/chart_cubic.h"
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
