// geometry/pose.h and the SE(3) geometries' twist conversions (V1, A1 in screw_se3.h; V2, A2 in
// double_geodesic_se3.h): the tangents of exponential motions against their spatial kinematics
// (quaternion differentiation, kinematicsFromJet) and against finite differences of the chart.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

#include "se3_interpolation/geometry/geometry.h"
#include "spline_test_utils.h"
#include "test_utils.h"

using namespace se3_interpolation;
using namespace se3_interpolation::test;

template <class G>
class TwistConversion : public ::testing::Test
{
};
TYPED_TEST_SUITE(TwistConversion, test::Se3Geometries);

// ---- twist conversions -------------------------------------------------------------------

TYPED_TEST(TwistConversion, TangentsOfExponentialMotionsMatchTheirSpatialKinematics)
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

TYPED_TEST(TwistConversion, TangentConversionsMatchFiniteDifferencesOfTheChart)
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
