// curves/interpolating_solver.h: the solve allocates a fixed number of buffers, whatever the
// number of waypoints and of Newton iterations (no heap allocation per iteration or
// per waypoint for the SE(3) geometries, whose frames are the identity), and the double
// geodesic's rotation-only transition derivatives agree with the generic 21-jet ones.
#include <gtest/gtest.h>

#include <random>

#include "se3_interpolation/curves/interpolating_spline.h"
#include "allocation_counter.h"
#include "test_utils.h"

using namespace se3_interpolation;

namespace
{
/// A random walk of rotation steps 0.2 … `max_angle` rad and translations ~ N(0, 0.5²).
std::vector<Pose<double>> walk(std::size_t n, double max_angle, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(0.2, max_angle);
  std::normal_distribution<double> nd(0.0, 0.5);
  std::vector<Pose<double>> x{ test::randomPose(rng) };
  for (std::size_t i = 1; i < n; ++i)
    x.push_back(x.back() * Pose<double>(so3Exp<double>(Eigen::Vector3d(angle(rng) * test::randomUnitVector<3>(rng))),
                                        Eigen::Vector3d(nd(rng), nd(rng), nd(rng))));
  return x;
}

template <class G>
long solveAllocations(std::size_t n, double max_angle, EndCondition condition)
{
  const std::vector<Pose<double>> x = walk(n, max_angle, 7);
  std::vector<double> t(n);
  for (std::size_t i = 0; i < n; ++i)
    t[i] = 0.5 * static_cast<double>(i) + 0.1 * static_cast<double>(i % 3);
  const Vector6<double> v0 = Vector6<double>::Constant(0.1), v1 = Vector6<double>::Constant(-0.2);
  const long before = test::allocationCount().load();
  const auto curve = solveC2Spline<G>(x, t, condition, v0, v1);
  const long after = test::allocationCount().load();
  EXPECT_EQ(curve->startRates().size(), n - 1);
  return after - before;
}
}  // namespace

template <class G>
class InterpolatingSolver : public ::testing::Test
{
};
using Se3Geometries = ::testing::Types<DoubleGeodesicSe3, ScrewSe3>;
TYPED_TEST_SUITE(InterpolatingSolver, Se3Geometries);

// 20 and 2000 waypoints, rotation steps up to 0.4 and up to 2 rad: the same number of
// allocations, natural and clamped. The previous solve made about 75 per waypoint.
TYPED_TEST(InterpolatingSolver, AllocationsDoNotGrowWithWaypointsOrIterations)
{
  for (const EndCondition condition : { EndCondition::kNatural, EndCondition::kClamped })
  {
    const long small = solveAllocations<TypeParam>(20, 0.4, condition);
    const long large = solveAllocations<TypeParam>(2000, 0.4, condition);
    const long hard = solveAllocations<TypeParam>(2000, 2.0, condition);
    EXPECT_EQ(small, large);
    EXPECT_EQ(small, hard);
    EXPECT_LT(small, 40);
  }
}

// The double geodesic's D and Q from the rotation's 6 jets (and D = I, Q = 0 on the
// translation) against chart_cubic.h's transitionDerivatives over all 6 coordinates (21 jets),
// at hard rotation steps: 1e-12 rad, 1, 3 rad and π − 1e-6.
TEST(InterpolatingSolverDerivatives, DoubleGeodesicRotationBlockMatchesTheFullJetComputation)
{
  std::mt19937 rng(3);
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(6, 6);
  for (const double angle : { 1e-12, 1.0, 3.0, M_PI - 1e-6 })
  {
    const Pose<double> x0 = test::randomPose(rng);
    const Pose<double> x1 = x0 * Pose<double>(so3Exp<double>(Eigen::Vector3d(angle * test::randomUnitVector<3>(rng))),
                                              Eigen::Vector3d(0.3, -1.0, 2.0));
    const Vector6<double> log = DoubleGeodesicSe3::log(x0, x1);
    const TransitionDerivatives full = transitionDerivatives<DoubleGeodesicSe3>(x0, x1, log, identity, identity);
    Eigen::Matrix3d d;
    Eigen::Matrix<double, 3, 9> q;
    detail::unitFrameTransition<So3, 3>(x0.q, x1.q, Eigen::Vector3d(log.head<3>()), &d, &q);
    const Eigen::Matrix3d rotation = full.jacobian.topLeftCorner(3, 3);
    const Eigen::Matrix3d translation = full.jacobian.bottomRightCorner(3, 3);
    EXPECT_LT((rotation - d).cwiseAbs().maxCoeff(), 1e-12) << angle;
    EXPECT_LT((translation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(full.jacobian.topRightCorner(3, 3).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(full.jacobian.bottomLeftCorner(3, 3).cwiseAbs().maxCoeff(), 1e-12);
    for (int j = 0; j < 6; ++j)
      for (int k = 0; k < 6; ++k)
      {
        const Eigen::VectorXd column = full.quadratic.col(j * 6 + k);
        if (j < 3 && k < 3)
        {
          EXPECT_LT((column.head<3>() - q.col(j * 3 + k)).cwiseAbs().maxCoeff(), 1e-10) << angle << " " << j << k;
          EXPECT_LT(column.tail<3>().cwiseAbs().maxCoeff(), 1e-12);
        }
        else
        {
          EXPECT_LT(column.cwiseAbs().maxCoeff(), 1e-12) << angle << " " << j << k;
        }
      }
  }
}

// The screw geometry's D and Q in closed form (the right Jacobian of SE(3) and its derivatives,
// detail::screwTransitionDerivatives) against the second-order jets of the transition map itself
// (unitFrameTransition, 21 jets of Log(x1⁻¹ x0 Exp(L + δ))), at hard rotation steps (0, 1e-12,
// the rate series' range, half a turn, π − 1e-6) and translations from 0 to 5 m.
TEST(InterpolatingSolverDerivatives, ScrewClosedFormMatchesTheJetsOfTheTransitionMap)
{
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const double angle : { 0.0, 1e-12, 1e-4, 0.05, 1.0, 3.0, M_PI - 1e-6 })
    for (const double reach : { 0.0, 0.1, 5.0 })
      for (int i = 0; i < 5; ++i)
      {
        const Pose<double> x0 = test::randomPose(rng);
        const Pose<double> x1 =
            x0 * Pose<double>(so3Exp<double>(Eigen::Vector3d(angle * test::randomUnitVector<3>(rng))),
                              Eigen::Vector3d(reach * u(rng), reach * u(rng), reach * u(rng)));
        const Vector6<double> log = ScrewSe3::log(x0, x1);
        Eigen::Matrix<double, 6, 6> d_jets, d_closed;
        Eigen::Matrix<double, 6, 36> q_jets, q_closed;
        detail::unitFrameTransition<ScrewSe3, 6>(x0, x1, log, &d_jets, &q_jets);
        detail::screwTransitionDerivatives(log, &d_closed, &q_closed);
        const double scale = 1.0 + log.squaredNorm();
        EXPECT_LT((d_jets - d_closed).cwiseAbs().maxCoeff(), 1e-12 * scale) << angle << " " << reach;
        EXPECT_LT((q_jets - q_closed).cwiseAbs().maxCoeff(), 1e-10 * scale) << angle << " " << reach;
        if (log.norm() > 0.5)  // not comparing zeros
        {
          EXPECT_GT(q_closed.cwiseAbs().maxCoeff(), 0.05) << angle << " " << reach;
        }
      }
}
