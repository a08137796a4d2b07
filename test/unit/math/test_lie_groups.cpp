// SO(3)/SE(3) exp and log against independent references (Eigen's AngleAxis and the
// matrix exponential of unsupported/MatrixFunctions), random samples and hard points.
#include <gtest/gtest.h>

#include <unsupported/Eigen/MatrixFunctions>

#include <random>

#include "se3_interpolation/math/lie_groups.h"
#include "test_utils.h"

using namespace se3_interpolation;
using se3_interpolation::test::randomUnitVector;

namespace
{
Eigen::Matrix4d twistMatrix(const Vector6<double>& xi)
{
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m.topLeftCorner<3, 3>() = hat<double>(xi.head<3>());
  m.topRightCorner<3, 1>() = xi.tail<3>();
  return m;
}

Eigen::Matrix4d poseMatrix(const Pose<double>& g)
{
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = g.q.toRotationMatrix();
  m.topRightCorner<3, 1>() = g.p;
  return m;
}

/// Angles that stress the closed forms: exact zero, tiny, series switch-over, near π.
const double kHardAngles[] = { 0.0, 1e-300, 1e-12, 1e-8, 1e-4, 0.19999999, 0.2, 0.20000001, 1.0, 3.0,
                               M_PI - 1e-6, M_PI - 1e-9 };
}  // namespace

TEST(So3, ExpMatchesAngleAxis)
{
  std::mt19937 rng(1);
  for (int i = 0; i < 10000; ++i)
  {
    const Eigen::Vector3d axis = randomUnitVector<3>(rng);
    const double angle = std::uniform_real_distribution<double>(0.0, M_PI)(rng);
    const Eigen::Quaterniond ref(Eigen::AngleAxisd(angle, axis));
    const Quaternion<double> q = so3Exp<double>(angle * axis);
    EXPECT_LT((q.coeffs() - ref.coeffs()).norm(), 1e-15);
  }
}

TEST(So3, LogExpRoundTripRandom)
{
  std::mt19937 rng(2);
  for (int i = 0; i < 10000; ++i)
  {
    const double angle = std::uniform_real_distribution<double>(0.0, M_PI - 1e-6)(rng);
    const Eigen::Vector3d w = angle * randomUnitVector<3>(rng);
    const Eigen::Vector3d back = so3Log(so3Exp<double>(w));
    EXPECT_LE((back - w).norm(), 1e-14 * std::max(1.0, w.norm())) << w.transpose();
  }
}

TEST(So3, HardPointsRelativeAccuracy)
{
  std::mt19937 rng(3);
  for (double angle : kHardAngles)
    for (int k = 0; k < 20; ++k)
    {
      const Eigen::Vector3d axis = randomUnitVector<3>(rng);
      // Reference quaternion built from the half angle directly (no cancellation anywhere).
      const Quaternion<double> q(std::cos(angle / 2), std::sin(angle / 2) * axis.x(), std::sin(angle / 2) * axis.y(),
                                 std::sin(angle / 2) * axis.z());
      const Eigen::Vector3d w = so3Log(q);
      EXPECT_LE((w - angle * axis).norm(), 1e-12 * angle + 1e-300) << "angle " << angle;
      const Quaternion<double> back = so3Exp<double>(w);
      EXPECT_LE((back.coeffs() - q.coeffs()).norm(), 1e-15) << "angle " << angle;  // a few ulps
    }
}

TEST(So3, SignOfQuaternionDoesNotMatter)
{
  std::mt19937 rng(4);
  for (double angle : kHardAngles)
  {
    const Eigen::Vector3d axis = randomUnitVector<3>(rng);
    const Quaternion<double> q = so3Exp<double>(angle * axis);
    const Quaternion<double> neg(-q.w(), -q.x(), -q.y(), -q.z());
    EXPECT_EQ(so3Log(q), so3Log(neg)) << angle;
  }
}

TEST(So3, ExactlyPiIsNotUnique)
{
  EXPECT_THROW(so3Log(Quaternion<double>(0.0, 1.0, 0.0, 0.0)), NonUniqueGeodesicError);
  EXPECT_THROW(so3Log(Quaternion<double>(-0.0, 0.0, 0.6, 0.8)), NonUniqueGeodesicError);
  EXPECT_NO_THROW(so3Log(so3Exp<double>(Eigen::Vector3d(M_PI - 1e-9, 0, 0))));
}

TEST(Se3, ExpMatchesMatrixExponential)
{
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 2000; ++i)
  {
    const double angle = i < 200 ? kHardAngles[i % 12] : std::uniform_real_distribution<double>(0.0, M_PI)(rng);
    Vector6<double> xi;
    xi << angle * randomUnitVector<3>(rng), n(rng), n(rng), n(rng);
    const Eigen::Matrix4d ref = twistMatrix(xi).exp();
    const Eigen::Matrix4d got = poseMatrix(se3Exp<double>(xi));
    EXPECT_LT((ref - got).norm(), 1e-13) << xi.transpose();
  }
}

TEST(Se3, LogExpRoundTripRandomAndHardPoints)
{
  std::mt19937 rng(6);
  std::normal_distribution<double> n(0.0, 2.0);
  for (int i = 0; i < 10000; ++i)
  {
    const double angle = i < 1200 ? kHardAngles[i % 12] : std::uniform_real_distribution<double>(0.0, M_PI - 1e-6)(rng);
    Vector6<double> xi;
    xi << angle * randomUnitVector<3>(rng), n(rng), n(rng), n(rng);
    const Vector6<double> back = se3Log(se3Exp<double>(xi));
    // The translation part's conditioning grows like 1/(π − θ) near π.
    const double cond = 1.0 / std::max(1e-3, M_PI - angle);
    EXPECT_LE((back - xi).norm(), 1e-14 * cond * std::max(1.0, xi.norm())) << xi.transpose();
  }
}

TEST(Se3, LogMatchesMatrixLogarithm)
{
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 500; ++i)
  {
    const Pose<double> g(so3Exp<double>(std::uniform_real_distribution<double>(0.0, 3.0)(rng) * randomUnitVector<3>(rng)),
                         Eigen::Vector3d(n(rng), n(rng), n(rng)));
    const Eigen::Matrix4d ref = poseMatrix(g).log();
    const Eigen::Matrix4d got = twistMatrix(se3Log(g));
    EXPECT_LT((ref - got).norm(), 1e-12);
  }
}

TEST(Se3, PoseCompositionAndInverse)
{
  std::mt19937 rng(8);
  for (int i = 0; i < 100; ++i)
  {
    const Pose<double> a = test::randomPose(rng);
    const Pose<double> b = test::randomPose(rng);
    EXPECT_LT((poseMatrix(a * b) - poseMatrix(a) * poseMatrix(b)).norm(), 1e-14);
    EXPECT_LT((poseMatrix(a.inverse()) - poseMatrix(a).inverse()).norm(), 1e-13);
  }
}

TEST(Se3, ConstantTimesJetPoseIsTheMatrixProductOfTheJets)
{
  // constantTimes(a, b) coefficient by coefficient against the 4×4 matrices: a's times each of b's
  // jet coefficients (the product is linear in b).
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 50; ++i)
  {
    const Pose<double> a = test::randomPose(rng);
    Pose<Jet<2>> b = test::randomPose(rng).cast<Jet<2>>();
    for (int c = 0; c < 4; ++c)
      for (int k = 1; k <= 2; ++k)
        b.q.coeffs()[c].coefficient(k) = u(rng);
    for (int c = 0; c < 3; ++c)
      for (int k = 1; k <= 2; ++k)
        b.p[c].coefficient(k) = u(rng);
    const Pose<Jet<2>> product = constantTimes(a, b);
    for (int k = 0; k <= 2; ++k)
    {
      Eigen::Quaterniond qb(b.q.w().coefficient(k), b.q.x().coefficient(k), b.q.y().coefficient(k), b.q.z().coefficient(k));
      const Eigen::Quaterniond expected_q = a.q * qb;
      const Eigen::Vector3d pb(b.p[0].coefficient(k), b.p[1].coefficient(k), b.p[2].coefficient(k));
      const Eigen::Vector3d expected_p = a.q.toRotationMatrix() * pb + (k == 0 ? a.p : Eigen::Vector3d::Zero());
      EXPECT_NEAR(product.q.w().coefficient(k), expected_q.w(), 1e-14);
      for (int c = 0; c < 3; ++c)
      {
        EXPECT_NEAR(product.q.vec()[c].coefficient(k), expected_q.vec()[c], 1e-14);
        EXPECT_NEAR(product.p[c].coefficient(k), expected_p[c], 1e-13);
      }
    }
  }
}

namespace
{
/// Interpolation parameters for the slerp tests: the ends, inside, and extrapolation.
const double kLambdas[] = { 0.0, 1e-3, 0.25, 0.5, 0.9, 1.0, -0.4, 1.6 };

/// q_a (q_a* q_b)^λ in long double through the relative quaternion and atan2 (the Log/Exp form,
/// not the slerp weights of so3Slerp).
Eigen::Vector4d slerpLongDouble(const Quaternion<double>& qa, const Quaternion<double>& qb, double lambda)
{
  using L = long double;
  const Eigen::Quaternion<L> a(L(qa.w()), L(qa.x()), L(qa.y()), L(qa.z()));
  Eigen::Quaternion<L> rel = a.conjugate() * Eigen::Quaternion<L>(L(qb.w()), L(qb.x()), L(qb.y()), L(qb.z()));
  if (rel.w() < 0)
    rel.coeffs() = -rel.coeffs();
  const L n = rel.vec().norm();
  const L phi = std::atan2(n, rel.w());
  Eigen::Quaternion<L> power(std::cos(L(lambda) * phi), 0, 0, 0);
  power.vec() = n > 0 ? Eigen::Matrix<L, 3, 1>(rel.vec() * (std::sin(L(lambda) * phi) / n))
                      : Eigen::Matrix<L, 3, 1>(rel.vec() * L(lambda));
  return (a * power).coeffs().cast<double>();
}
}  // namespace

TEST(So3Slerp, FromIdentityRelativeAccuracyAtHardAngles)
{
  std::mt19937 rng(21);
  for (double angle : kHardAngles)
    for (int k = 0; k < 10; ++k)
    {
      const Eigen::Vector3d axis = randomUnitVector<3>(rng);
      const Quaternion<double> b(std::cos(angle / 2), std::sin(angle / 2) * axis.x(), std::sin(angle / 2) * axis.y(),
                                 std::sin(angle / 2) * axis.z());
      for (double lambda : kLambdas)
      {
        // (cos(λθ/2), sin(λθ/2) axis): the closed form of the power of a rotation about one axis.
        const double half = lambda * angle / 2;
        const Eigen::Vector3d vec = std::sin(half) * axis;
        for (const double sign : { 1.0, -1.0 })
        {
          Quaternion<double> bs;
          bs.coeffs() = sign * b.coeffs();
          const Quaternion<double> r = so3Slerp(Quaternion<double>::Identity(), bs, lambda);
          EXPECT_LE((r.vec() - vec).norm(), 1e-12 * vec.norm() + 1e-300) << "angle " << angle << " lambda " << lambda;
          EXPECT_LE(std::abs(r.w() - std::cos(half)), 2e-16) << "angle " << angle << " lambda " << lambda;
        }
      }
    }
}

TEST(So3Slerp, MatchesLongDoubleAndLogExpPath)
{
  std::mt19937 rng(22);
  for (double angle : kHardAngles)
    for (int k = 0; k < 10; ++k)
    {
      const Quaternion<double> a = so3Exp<double>(std::uniform_real_distribution<double>(0.0, 3.1)(rng) *
                                                  randomUnitVector<3>(rng));
      const Quaternion<double> b = a * so3Exp<double>(angle * randomUnitVector<3>(rng));
      for (double lambda : kLambdas)
      {
        const Quaternion<double> r = so3Slerp(a, b, lambda);
        // The quaternion's components are of order 1: a few ulps absolute (the cancellation in
        // q_a* q_b is the inputs' condition, shared by every method).
        EXPECT_LE((r.coeffs() - slerpLongDouble(a, b, lambda)).norm(), 2e-15)
            << "angle " << angle << " lambda " << lambda;
        const Quaternion<double> generic =
            a * so3Exp<double>(Eigen::Vector3d(so3Log(Quaternion<double>(a.conjugate() * b)) * lambda));
        EXPECT_LE(rotationAngle(Quaternion<double>(generic.conjugate() * r)), 1e-14)
            << "angle " << angle << " lambda " << lambda;
      }
    }
}

TEST(So3Slerp, ExactlyPiIsNotUnique)
{
  const Quaternion<double> a = so3Exp<double>(Eigen::Vector3d(0.3, -0.2, 0.5));
  const Quaternion<double> b = a * Quaternion<double>(0.0, 0.0, 1.0, 0.0);
  EXPECT_THROW(so3Slerp(a, b, 0.5), NonUniqueGeodesicError);
}

TEST(ScrewCoefficients, RatesAreTheDerivativesOfAAndBOnBothSidesOfTheSeriesSwitch)
{
  // dA/dx and dB/dx (x = θ²) against references written here in long double: the θ-derivatives of
  // A = (1 − cos θ)/θ² and B = (θ − sin θ)/θ³ divided by dx/dθ = 2θ where they do not cancel
  // (θ ≥ 1.5), their Taylor series summed to 20 terms below; at angle 0, across the switch at
  // θ² = 1, up to θ = π − 1e-9 and beyond (the chart cubic's tangents may exceed π).
  const auto reference = [](long double x, long double* da, long double* db) {
    if (x >= 2.25L)
    {
      const long double t = std::sqrt(x);
      *da = (t * std::sin(t) - 2.0L * (1.0L - std::cos(t))) / (2.0L * x * x);
      *db = ((1.0L - std::cos(t)) * t - 3.0L * (t - std::sin(t))) / (2.0L * x * x * t);
      return;
    }
    *da = *db = 0.0L;
    long double factorial = 2.0L;  // (2k + 2)! at k = 0
    long double power = 1.0L;      // x^(k − 1) at k = 1
    for (int k = 1; k < 20; ++k)
    {
      factorial *= (2.0L * k + 1.0L) * (2.0L * k + 2.0L);
      const long double sign = k % 2 == 0 ? 1.0L : -1.0L;
      *da += sign * k * power / factorial;
      *db += sign * k * power / (factorial * (2.0L * k + 3.0L));
      power *= x;
    }
  };
  std::vector<double> xs{ 0.0, 1e-18, 1e-8, 1e-4, 0.01, 0.02, 0.04, 0.1, 0.5, 1.0 - 1e-12, 1.0, 1.0 + 1e-12, 1.5, 4.0 };
  const double pi = 3.14159265358979323846;
  xs.push_back((pi - 1e-9) * (pi - 1e-9));
  xs.push_back(30.0);
  std::mt19937 rng(7);
  for (int i = 0; i < 40; ++i)
    xs.push_back(std::uniform_real_distribution<double>(0.0, 12.0)(rng));
  for (const double x : xs)
  {
    const detail::ScrewCoefficients coefficients = detail::screwCoefficients(x);
    const double da = coefficients.da, db = coefficients.db;
    long double ra, rb;
    reference(x, &ra, &rb);
    EXPECT_NEAR(da, static_cast<double>(ra), 3e-14 * std::abs(static_cast<double>(ra))) << "x = " << x;
    EXPECT_NEAR(db, static_cast<double>(rb), 3e-14 * std::abs(static_cast<double>(rb))) << "x = " << x;
  }
}

TEST(ScrewCoefficients, SecondDerivativesOfAAndBOnBothSidesOfTheSeriesSwitch)
{
  // d²A/dx² and d²B/dx² (x = θ²) against references written here in long double: below x = 9
  // their Taylor series Σ_{k≥2} (−1)^k k (k − 1) x^(k−2)/(2k+2)! (and /(2k+3)!) summed to 30 terms;
  // above it the θ-derivatives, d²f/dx² = (f_θθ − f_θ/θ)/(4θ²), from A = (1 − cos θ)/θ² and
  // B = 1/θ² − sin θ/θ³. At angle 0, across the switch at θ² = 4 and the first rates' at θ² = 1,
  // up to θ = π − 1e-9 and beyond.
  const auto reference = [](long double x, long double* dda, long double* ddb) {
    if (x >= 9.0L)
    {
      const long double t = std::sqrt(x), s = std::sin(t), c = std::cos(t);
      const long double a1 = s / (t * t) - 2.0L * (1.0L - c) / (t * t * t);
      const long double a2 = c / (t * t) - 4.0L * s / (t * t * t) + 6.0L * (1.0L - c) / (x * x);
      const long double b1 = -2.0L / (t * t * t) - c / (t * t * t) + 3.0L * s / (x * x);
      const long double b2 = 6.0L / (x * x) + s / (t * t * t) + 6.0L * c / (x * x) - 12.0L * s / (x * x * t);
      *dda = (a2 - a1 / t) / (4.0L * x);
      *ddb = (b2 - b1 / t) / (4.0L * x);
      return;
    }
    *dda = *ddb = 0.0L;
    long double factorial = 24.0L;  // (2k + 2)! at k = 1
    long double power = 1.0L;       // x^(k − 2) at k = 2
    for (int k = 2; k < 32; ++k)
    {
      factorial *= (2.0L * k + 1.0L) * (2.0L * k + 2.0L);
      const long double sign = k % 2 == 0 ? 1.0L : -1.0L;
      *dda += sign * k * (k - 1) * power / factorial;
      *ddb += sign * k * (k - 1) * power / (factorial * (2.0L * k + 3.0L));
      power *= x;
    }
  };
  std::vector<double> xs{ 0.0,         1e-18, 1e-8, 1e-4, 0.04, 0.5, 1.0, 2.0, 4.0 - 1e-12, 4.0,
                          4.0 + 1e-12, 4.5,   6.0,  9.0,  30.0 };
  const double pi = 3.14159265358979323846;
  xs.push_back((pi - 1e-9) * (pi - 1e-9));
  std::mt19937 rng(8);
  for (int i = 0; i < 40; ++i)
    xs.push_back(std::uniform_real_distribution<double>(0.0, 12.0)(rng));
  for (const double x : xs)
  {
    const detail::ScrewSecondDerivatives d = detail::screwSecondDerivatives(x, detail::screwCoefficients(x));
    long double ra, rb;
    reference(x, &ra, &rb);
    EXPECT_NEAR(d.dda, static_cast<double>(ra), 1e-13 * std::abs(static_cast<double>(ra))) << "x = " << x;
    EXPECT_NEAR(d.ddb, static_cast<double>(rb), 1e-13 * std::abs(static_cast<double>(rb))) << "x = " << x;
  }
}
