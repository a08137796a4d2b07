// The start state braked to rest along its own directions (curves/braked_start.h, B1, B2), checked
// against the classical constant-deceleration formulas and finite differences of its poses.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/curves/braked_start.h"
#include "se3_interpolation/geometry/double_geodesic_se3.h"
#include "se3_interpolation/geometry/screw_se3.h"
#include "test_utils.h"

namespace se3_interpolation
{
namespace
{
BrakeToRest brakeOf(const Pose<double>& start, const Twist& velocity, const Twist& acceleration, double a, double alpha)
{
  BrakeToRest b;
  b.start = start;
  b.start_acceleration = acceleration;
  b.linear.speed = velocity.linear.norm();
  b.linear.direction = velocity.linear / b.linear.speed;
  b.linear.deceleration = a;
  b.angular.speed = velocity.angular.norm();
  b.angular.direction = velocity.angular / b.angular.speed;
  b.angular.deceleration = alpha;
  return b;
}

template <class G>
class BrakedStart : public ::testing::Test
{
};
using Geometries = ::testing::Types<DoubleGeodesicSe3, ScrewSe3>;
TYPED_TEST_SUITE(BrakedStart, Geometries);

// The braking from (v0, ω0) at (a, α), then a straight segment from the stopping pose:
//  - the first state from the left is the start state (pose, twist, acceleration);
//  - the speeds fall at exactly a and α until T_l = |v0|/a and T_a = |ω0|/α, along fixed directions,
//    and the stopping pose is p0 + v̂ |v0|²/(2a), exp(ŵ |ω0|²/(2α)) R0 (the classical formulas);
//  - velocities and accelerations agree with central differences of the poses;
//  - after T = max(T_l, T_a) the curve is the rest shifted to begin at T.
TYPED_TEST(BrakedStart, BrakesAtTheGivenDecelerationsToTheClassicalStop)
{
  const Pose<double> start(Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -0.5).normalized())),
                           Eigen::Vector3d(0.3, -0.2, 0.5));
  Twist v, a0;
  v.linear = Eigen::Vector3d(0.9, -0.3, 0.2);
  v.angular = Eigen::Vector3d(0.1, 0.4, -0.2);
  a0.linear = Eigen::Vector3d(-0.6, 0.2, 0.1);
  a0.angular = Eigen::Vector3d(0.4, 0.1, -0.7);
  const double a = 0.5, alpha = 0.8;
  const BrakeToRest brake = brakeOf(start, v, a0, a, alpha);
  const double tl = v.linear.norm() / a, ta = v.angular.norm() / alpha;
  EXPECT_NEAR(brake.stopTime(), std::max(tl, ta), 1e-15);
  const Pose<double> stop = brake.stopPose();
  const Eigen::Vector3d expected_p = start.p + v.linear.normalized() * v.linear.squaredNorm() / (2 * a);
  const Eigen::Quaterniond expected_q =
      Eigen::Quaterniond(Eigen::AngleAxisd(v.angular.squaredNorm() / (2 * alpha), v.angular.normalized())) *
      Eigen::Quaterniond(start.q.w(), start.q.x(), start.q.y(), start.q.z());
  EXPECT_LT((stop.p - expected_p).norm(), 1e-14);
  EXPECT_LT(std::abs(std::abs(stop.q.coeffs().dot(Eigen::Vector4d(expected_q.x(), expected_q.y(), expected_q.z(), expected_q.w()))) - 1.0), 1e-14);

  const std::vector<Pose<double>> line{ stop, Pose<double>(stop.q, stop.p + Eigen::Vector3d(0.0, 0.0, 1.0)) };
  auto rest = std::make_shared<BezierCurve<TypeParam>>(line, 0.0, 2.0);
  const BrakedStartCurve<TypeParam> curve(brake, rest);
  const double T = curve.stopTime();
  EXPECT_EQ(curve.endTime(), T + 2.0);
  const std::vector<double> b = curve.breakpoints();
  ASSERT_EQ(b.size(), 4u);
  EXPECT_EQ(b[1], std::min(tl, ta));
  EXPECT_EQ(b[2], T);

  const Kinematics first = kinematicsAt(curve, 0.0, Side::kLeft);
  EXPECT_LT(test::poseDistance(first.pose, start), 1e-15);
  EXPECT_LT((first.velocity.linear - v.linear).norm(), 1e-14);
  EXPECT_LT((first.velocity.angular - v.angular).norm(), 1e-14);
  EXPECT_LT((first.acceleration.linear - a0.linear).norm(), 1e-14);
  EXPECT_LT((first.acceleration.angular - a0.angular).norm(), 1e-14);

  const double h = 1e-5;
  for (int k = 1; k < 200; ++k)
  {
    const double t = T * k / 200.0;
    if (std::abs(t - tl) < 2 * h || std::abs(t - ta) < 2 * h)
      continue;
    const Kinematics x = kinematicsAt(curve, t);
    const double linear = std::max(0.0, v.linear.norm() - a * t), angular = std::max(0.0, v.angular.norm() - alpha * t);
    EXPECT_NEAR(x.velocity.linear.norm(), linear, 1e-13) << t;
    EXPECT_NEAR(x.velocity.angular.norm(), angular, 1e-13) << t;
    EXPECT_NEAR(x.acceleration.linear.norm(), t < tl ? a : 0.0, 1e-13) << t;
    EXPECT_NEAR(x.acceleration.angular.norm(), t < ta ? alpha : 0.0, 1e-13) << t;
    if (t < tl)
      EXPECT_LT((x.velocity.linear.normalized() - v.linear.normalized()).norm(), 1e-12) << t;
    if (t < ta)
      EXPECT_LT((x.velocity.angular.normalized() - v.angular.normalized()).norm(), 1e-12) << t;
    // Central differences of the poses (the angular velocity from R(t+h) R(t−h)^T).
    const Pose<double> before = curve.value(t - h), after = curve.value(t + h), here = curve.value(t);
    EXPECT_LT(((after.p - before.p) / (2 * h) - x.velocity.linear).norm(), 1e-8) << t;
    EXPECT_LT(((after.p - 2 * here.p + before.p) / (h * h) - x.acceleration.linear).norm(), 1e-4) << t;
    const Eigen::Vector3d omega = so3Log<double>(after.q * before.q.conjugate()) / (2 * h);
    EXPECT_LT((omega - x.velocity.angular).norm(), 1e-8) << t;
  }
  // After the stop: the rest from its start.
  for (double u : { 0.0, 0.5, 1.3, 2.0 })
  {
    const Kinematics x = kinematicsAt(curve, T + u, u == 2.0 ? Side::kLeft : Side::kRight);
    const Kinematics y = kinematicsAt(*rest, u, u == 2.0 ? Side::kLeft : Side::kRight);
    EXPECT_LT(test::poseDistance(x.pose, y.pose), 1e-14) << u;
    EXPECT_LT((x.velocity.linear - y.velocity.linear).norm(), 1e-14) << u;
  }
  EXPECT_LT(test::poseDistance(curve.value(curve.endTime()), line.back()), 1e-15);
}

TEST(BrakedStart, NoStopIsRefusedNamingTheStartState)
{
  BrakeToRest still;
  auto rest = std::make_shared<BezierCurve<DoubleGeodesicSe3>>(
      std::vector<Pose<double>>{ Pose<double>(), Pose<double>(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0)) },
      0.0, 1.0);
  try
  {
    BrakedStartCurve<DoubleGeodesicSe3> curve(still, rest);
    ADD_FAILURE() << "a braking of no duration was accepted";
  }
  catch (const InvalidInputError& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("start_state:", 0), 0u) << e.what();
  }
}
}  // namespace
}  // namespace se3_interpolation
