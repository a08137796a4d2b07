// geometry/tangent_space.h: the acceleration (T2) of a curve in a geometry's tangent
// representation, against the rate of the body twist computed independently.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

#include "se3_interpolation/geometry/tangent_space.h"
#include "spline_test_utils.h"
#include "test_utils.h"

using namespace se3_interpolation;
using namespace se3_interpolation::test;

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
