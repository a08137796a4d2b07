// curves/hermite.h: Hermite cubics (Crouch Case 1) have the given velocities at every waypoint,
// reduce to the classical Hermite cubic for translations, and estimate tangents exactly for
// quadratic motions; too-large velocities are refused by name.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

#include "se3_interpolation/curves/hermite.h"
#include "spline_test_utils.h"
#include "test_utils.h"

using namespace se3_interpolation;
using namespace se3_interpolation::test;

template <class G>
class HermiteSe3 : public ::testing::Test
{
};
TYPED_TEST_SUITE(HermiteSe3, test::Se3Geometries);

// ---- hermite ---------------------------------------------------------------------------------

TYPED_TEST(HermiteSe3, HermiteHasTheGivenVelocityAtEveryWaypoint)
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

TYPED_TEST(HermiteSe3, HermiteForTranslationsIsTheClassicalHermite)
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
