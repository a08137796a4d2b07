// Geodesics and Bézier curves (de Casteljau) on SE(3): thesis Prop. 4.2.1–4.2.4 and 4.2.8,
// the classical Bernstein form in the abelian cases, invariances, analytic derivatives.
#include <gtest/gtest.h>

#include <random>

#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/curves/bezier.h"
#include "test_utils.h"

using namespace se3_interpolation;
using test::poseDistance;
using test::randomPolygon;
using test::randomPose;

namespace
{
double binomial(int n, int k)
{
  double r = 1.0;
  for (int i = 1; i <= k; ++i)
    r = r * (n - k + i) / i;
  return r;
}

template <class G>
Pose<double> bezierAt(const std::vector<Pose<double>>& pts, double lambda)
{
  return BezierCurve<G>(pts, 0.0, 1.0).value(lambda);
}

template <class G>
class GeometryTest : public ::testing::Test
{
};
using SE3Geometries = ::testing::Types<ScrewSe3, DoubleGeodesicSe3>;
TYPED_TEST_SUITE(GeometryTest, SE3Geometries);
}  // namespace

TEST(Geodesic, DoubleGeodesicIsSlerpPlusLerp)
{
  std::mt19937 rng(10);
  for (int i = 0; i < 1000; ++i)
  {
    const Pose<double> a = randomPose(rng), b = randomPose(rng);
    const double lambda = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    const Pose<double> g = geodesic<DoubleGeodesicSe3>(a, b, lambda);
    Eigen::Quaterniond qa(a.q), qb(b.q);
    const Eigen::Quaterniond ref = qa.slerp(lambda, qb);  // Eigen picks the shorter arc
    EXPECT_LT(std::min((g.q.coeffs() - ref.coeffs()).norm(), (g.q.coeffs() + ref.coeffs()).norm()), 1e-12);
    EXPECT_LT((g.p - ((1 - lambda) * a.p + lambda * b.p)).norm(), 1e-14);
  }
}

TEST(Geodesic, DoubleGeodesicSlerpKernelMatchesLogExpPath)
{
  // geodesic<DoubleGeodesicSe3, double> is the slerp-form kernel; exp(a, λ log(a, b)) written
  // out is the generic path it replaces. Hard relative angles and extrapolation included.
  std::mt19937 rng(11);
  for (const double angle : { 0.0, 1e-12, 1e-8, 0.2, 1.0, 3.0, M_PI - 1e-9 })
    for (int i = 0; i < 50; ++i)
    {
      const Pose<double> a = randomPose(rng);
      const Pose<double> b = a * Pose<double>(so3Exp<double>(angle * test::randomUnitVector<3>(rng)),
                                              Eigen::Vector3d::Random());
      const double lambda = std::uniform_real_distribution<double>(-0.5, 1.5)(rng);
      const Pose<double> g = geodesic<DoubleGeodesicSe3>(a, b, lambda);
      const Pose<double> ref =
          DoubleGeodesicSe3::exp(a, Vector6<double>(DoubleGeodesicSe3::log(a, b) * lambda));
      EXPECT_LT(poseDistance(g, ref), 1e-14) << "angle " << angle << " lambda " << lambda;
    }
}

namespace
{
/// Largest difference between the jet coefficients (value, first, second) of two jet poses.
double jetPoseDifference(const Pose<Jet<2>>& a, const Pose<Jet<2>>& b)
{
  double d = 0.0;
  for (int k = 0; k <= 2; ++k)
  {
    for (int i = 0; i < 4; ++i)
      d = std::max(d, std::abs(a.q.coeffs()[i].coefficient(k) - b.q.coeffs()[i].coefficient(k)));
    for (int i = 0; i < 3; ++i)
      d = std::max(d, std::abs(a.p[i].coefficient(k) - b.p[i].coefficient(k)));
  }
  return d;
}
}  // namespace

namespace
{
/// Largest difference between two kinematics (pose up to the quaternion's sign, rates).
double kinematicsDifference(const Kinematics& a, const Kinematics& b)
{
  const double q = std::min((a.pose.q.coeffs() - b.pose.q.coeffs()).cwiseAbs().maxCoeff(),
                            (a.pose.q.coeffs() + b.pose.q.coeffs()).cwiseAbs().maxCoeff());
  return std::max({ q, (a.pose.p - b.pose.p).cwiseAbs().maxCoeff(),
                    (a.velocity.angular - b.velocity.angular).cwiseAbs().maxCoeff(),
                    (a.velocity.linear - b.velocity.linear).cwiseAbs().maxCoeff(),
                    (a.acceleration.angular - b.acceleration.angular).cwiseAbs().maxCoeff(),
                    (a.acceleration.linear - b.acceleration.linear).cwiseAbs().maxCoeff() });
}
}  // namespace

TYPED_TEST(GeometryTest, ClosedFormFirstLevelJetMatchesJetArithmetic)
{
  // G::expLine (one-parameter subgroup derivatives) and G::expLineKinematics (a fixed rotation
  // axis, the body twist α̇ ξ) against exp evaluated in Jet<2> (geodesicFromLogGeneric) and its
  // kinematics, for linear parameter jets (a curve's first level) and jets with a second-order
  // term (a curve composed with a non-linear clock), at hard relative angles.
  using G = TypeParam;
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (const double angle : { 0.0, 1e-12, 1e-6, 0.2, 1.0, 2.5, M_PI - 1e-9 })
    for (int i = 0; i < 40; ++i)
    {
      const Pose<double> a = randomPose(rng);
      const Pose<double> b = a * Pose<double>(so3Exp<double>(angle * test::randomUnitVector<3>(rng)),
                                              Eigen::Vector3d(u(rng), u(rng), u(rng)));
      const Vector6<double> log = G::log(a, b);
      Jet<2> alpha = Jet<2>::variable(std::uniform_real_distribution<double>(-0.5, 1.5)(rng)) * u(rng);
      if (i % 2 == 1)
        alpha.coefficient(2) = u(rng);
      const Pose<Jet<2>> closed = geodesicFromLog<G>(a, log, alpha);
      const Pose<Jet<2>> generic = geodesicFromLogGeneric<G>(a, log, alpha);
      EXPECT_LE(jetPoseDifference(closed, generic), 1e-12) << "angle " << angle << " i " << i;
      EXPECT_LE(kinematicsDifference(G::expLineKinematics(a, log, alpha), kinematicsFromJet(generic)), 1e-12)
          << "angle " << angle << " i " << i;
      // The first-order closed form: the value and first coefficient of the generic second-order jet.
      Jet<1> alpha1(alpha.value());
      alpha1.coefficient(1) = alpha.coefficient(1);
      const Pose<Jet<1>> closed1 = geodesicFromLog<G>(a, log, alpha1);
      for (int k = 0; k <= 1; ++k)
      {
        for (int c = 0; c < 4; ++c)
          EXPECT_NEAR(closed1.q.coeffs()[c].coefficient(k), generic.q.coeffs()[c].coefficient(k), 1e-12)
              << "angle " << angle << " i " << i;
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(closed1.p[c].coefficient(k), generic.p[c].coefficient(k), 1e-12) << "angle " << angle << " i " << i;
      }
    }
}

TYPED_TEST(GeometryTest, PiecewiseGeodesicKinematicsMatchItsJets)
{
  // A piecewise geodesic's kinematicsAt (the closed form, G::expLineKinematics) against its own
  // jets on both sides of its waypoints, a 10 ms segment among them.
  using G = TypeParam;
  std::mt19937 rng(14);
  const std::vector<Pose<double>> points = randomPolygon(rng, 5);
  const std::vector<double> times{ 0.0, 0.3, 1.3, 1.31, 4.0 };
  const PiecewiseGeodesic<G> polygon(points, times);
  for (const double t : { 0.0, 0.1, 0.3, 1.0, 1.3, 1.305, 1.31, 2.5, 4.0 })
    for (const Side side : { Side::kLeft, Side::kRight })
    {
      const Kinematics jets = kinematicsFromJet(polygon.jet(Jet<2>::variable(t), side));
      EXPECT_LE(kinematicsDifference(kinematicsAt(polygon, t, side), jets), 1e-10) << "t " << t;
    }
}

TEST(Geodesic, So3ClosedFormFirstLevelJetMatchesJetArithmetic)
{
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (const double angle : { 0.0, 1e-12, 1.0, M_PI - 1e-9 })
    for (int i = 0; i < 40; ++i)
    {
      const Quaternion<double> a = randomPose(rng).q;
      const Eigen::Vector3d log = angle * test::randomUnitVector<3>(rng);
      Jet<2> alpha = Jet<2>::variable(u(rng)) * u(rng);
      alpha.coefficient(2) = i % 2 == 1 ? u(rng) : 0.0;
      const Quaternion<Jet<2>> closed = geodesicFromLog<So3>(a, log, alpha);
      const Quaternion<Jet<2>> generic = geodesicFromLogGeneric<So3>(a, log, alpha);
      for (int c = 0; c < 4; ++c)
        for (int k = 0; k <= 2; ++k)
          EXPECT_NEAR(closed.coeffs()[c].coefficient(k), generic.coeffs()[c].coefficient(k), 1e-12)
              << "angle " << angle << " i " << i;
    }
}

namespace
{
/// Two poses `angle` rad and up to 2√3 m apart, and two unrelated tangents along which they move:
/// the configurations of the jet steps' tests.
struct MovingPair
{
  Pose<double> a, b;
  Vector6<double> la, lb;
};
MovingPair movingPair(std::mt19937& rng, double angle)
{
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  MovingPair pair;
  pair.a = randomPose(rng);
  pair.b = pair.a * Pose<double>(so3Exp<double>(angle * test::randomUnitVector<3>(rng)),
                                 Eigen::Vector3d(u(rng), u(rng), u(rng)));
  pair.la << u(rng) * test::randomUnitVector<3>(rng), u(rng), u(rng), u(rng);
  pair.lb << u(rng) * test::randomUnitVector<3>(rng), u(rng), u(rng), u(rng);
  return pair;
}
}  // namespace

TEST(Geodesic, SlerpJetStepMatchesLogExpJetPath)
{
  // geodesic<G, Jet<2>> for DoubleGeodesicSe3 and So3 (so3SlerpJet: closed-form weights above
  // θ = 0.05, their series in φ² below, the Log/Exp jet path for far extrapolations at small
  // angles) against exp(A, λ log(A, B)) written out in jets, between two jet poses moving along
  // unrelated geodesics with a curved clock, at relative angles across the switch-over.
  using DG = DoubleGeodesicSe3;
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (const double angle :
       { 0.0, 1e-12, 1e-4, 0.005, 0.02, 0.0499, 0.0501, 0.2, 1.0, 2.5, M_PI - 1e-6, M_PI - 1e-9 })
    for (int i = 0; i < 40; ++i)
    {
      const MovingPair pair = movingPair(rng, angle);
      Jet<2> alpha = Jet<2>::variable(0.0) * u(rng);
      alpha.coefficient(2) = u(rng);
      const Pose<Jet<2>> a = geodesicFromLogGeneric<DG>(pair.a, pair.la, alpha);
      const Pose<Jet<2>> b = geodesicFromLogGeneric<DG>(pair.b, pair.lb, Jet<2>(Jet<2>::variable(0.0) * u(rng)));
      // Below θ = 0.1 every tenth λ far out (λ = ±40: beyond the series' reach from θ ≈ 0.01).
      const double lambda0 =
          i % 10 == 9 && angle < 0.1 ? (i % 20 == 9 ? 40.0 : -40.0) : std::uniform_real_distribution<double>(-0.5, 1.5)(rng);
      const Jet<2> lambda = Jet<2>::variable(lambda0) * u(rng);
      const Pose<Jet<2>> ref = DG::exp(a, Vector6<Jet<2>>(DG::log(a, b) * lambda));
      // (Relative to the coefficients' size: an extrapolation to λ = 40 scales them by 40.)
      const double scale = 1.0 + std::abs(lambda0);
      EXPECT_LE(jetPoseDifference(geodesic<DG>(a, b, lambda), ref), 1e-12 * scale) << "angle " << angle << " i " << i;
      const Quaternion<Jet<2>> q = geodesic<So3>(a.q, b.q, lambda);
      EXPECT_LE(jetPoseDifference(Pose<Jet<2>>(q, ref.p), ref), 1e-12 * scale) << "angle " << angle << " i " << i;
    }
}

namespace
{
/// Largest difference between the coefficients of two jet poses of order K, relative to
/// 1 + the largest coefficient of the second.
template <int K>
double relativeJetPoseDifference(const Pose<Jet<K>>& a, const Pose<Jet<K>>& b)
{
  double d = 0.0;
  double scale = 1.0;
  for (int k = 0; k <= K; ++k)
  {
    for (int i = 0; i < 4; ++i)
    {
      d = std::max(d, std::abs(a.q.coeffs()[i].coefficient(k) - b.q.coeffs()[i].coefficient(k)));
      scale = std::max(scale, std::abs(b.q.coeffs()[i].coefficient(k)));
    }
    for (int i = 0; i < 3; ++i)
    {
      d = std::max(d, std::abs(a.p[i].coefficient(k) - b.p[i].coefficient(k)));
      scale = std::max(scale, std::abs(b.p[i].coefficient(k)));
    }
  }
  return d / scale;
}

/// geodesic<ScrewSe3, Jet<K>> (the slerp form: closed-form weights above θ = 0.05 at second order
/// and 0.2 at third, their series in φ² below, the Log → Exp jet path for far extrapolations at
/// small angles) against a Exp(λ Log(a⁻¹ b)) written out in jets, between two jet poses moving
/// along unrelated screws with a curved clock, at relative angles across the switch-overs and
/// near π.
template <int K>
void checkScrewSlerpJet(std::uint32_t seed)
{
  using J = Jet<K>;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  auto clock = [&]() {
    J alpha = J::variable(0.0) * u(rng);
    for (int k = 2; k <= K; ++k)
      alpha.coefficient(k) = u(rng);
    return alpha;
  };
  // The switch-overs: θ = 0.05 at second order, 0.2 at third (kScrewSlerpJetMinSine2); θ = 0.005
  // and 0.02 are inside the series' reach at λ = ±40 only for the first, not the second.
  for (const double angle : { 0.0, 1e-12, 1e-4, 0.005, 0.02, 0.0499, 0.0501, 0.1, 0.199, 0.201, 1.0, 2.5,
                              M_PI - 1e-6, M_PI - 1e-9 })
    for (int i = 0; i < 40; ++i)
    {
      const MovingPair pair = movingPair(rng, angle);
      const Pose<J> a = ScrewSe3::exp(pair.a.cast<J>(), Vector6<J>(pair.la.cast<J>() * clock()));
      const Pose<J> b = ScrewSe3::exp(pair.b.cast<J>(), Vector6<J>(pair.lb.cast<J>() * clock()));
      // Below θ = 0.1 every tenth λ far out (λ = ±40: beyond the series' reach from θ ≈ 0.01).
      const double lambda0 =
          i % 10 == 9 && angle < 0.1 ? (i % 20 == 9 ? 40.0 : -40.0) : std::uniform_real_distribution<double>(-0.5, 1.5)(rng);
      const J lambda = J::variable(lambda0) * u(rng);
      const Pose<J> ref = ScrewSe3::exp(a, Vector6<J>(ScrewSe3::log(a, b) * lambda));
      EXPECT_LE(relativeJetPoseDifference(geodesic<ScrewSe3>(a, b, lambda), ref), 1e-12)
          << "order " << K << " angle " << angle << " i " << i;
    }
}
}  // namespace

TEST(Geodesic, ScrewSlerpJetStepMatchesLogExpJetPath)
{
  checkScrewSlerpJet<2>(15);
  checkScrewSlerpJet<3>(16);
}

TEST(Geodesic, ScrewIsOneParameterSubgroupAndExtrapolates)
{
  std::mt19937 rng(11);
  for (int i = 0; i < 200; ++i)
  {
    const Pose<double> a = randomPose(rng), b = randomPose(rng);
    const Vector6<double> xi = se3Log((a.inverse() * b));
    for (double lambda : { -0.5, 0.0, 0.3, 1.0, 1.7 })
    {
      const Pose<double> g = geodesic<ScrewSe3>(a, b, lambda);
      EXPECT_LT(poseDistance(g, a * se3Exp<double>(lambda * xi)), 1e-12);
    }
    EXPECT_LT(poseDistance(geodesic<ScrewSe3>(a, b, 1.0), b), 1e-12);
    // Constant body twist: the geodesic composed of two halves is the whole.
    const Pose<double> half = geodesic<ScrewSe3>(a, b, 0.5);
    EXPECT_LT(poseDistance(geodesic<ScrewSe3>(a, half, 2.0), b), 1e-11);
  }
}

TYPED_TEST(GeometryTest, QuaternionSignDoesNotMatter)
{
  std::mt19937 rng(12);
  for (int i = 0; i < 100; ++i)
  {
    std::vector<Pose<double>> pts = randomPolygon(rng, 4);
    std::vector<Pose<double>> flipped = pts;
    flipped[1].q.coeffs() *= -1.0;
    flipped[3].q.coeffs() *= -1.0;
    for (double lambda : { 0.0, 0.25, 0.8, 1.0 })
      EXPECT_LT(poseDistance(bezierAt<TypeParam>(pts, lambda), bezierAt<TypeParam>(flipped, lambda)), 1e-13);
  }
}

TYPED_TEST(GeometryTest, BezierEqualsBernsteinForPureTranslations)
{
  std::mt19937 rng(13);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int degree = 1; degree <= 7; ++degree)
  {
    std::vector<Pose<double>> pts;
    for (int i = 0; i <= degree; ++i)
      pts.emplace_back(Quaternion<double>::Identity(), Eigen::Vector3d(n(rng), n(rng), n(rng)));
    for (double lambda : { 0.0, 0.1, 0.5, 0.77, 1.0 })
    {
      Eigen::Vector3d ref = Eigen::Vector3d::Zero();
      for (int i = 0; i <= degree; ++i)
        ref += binomial(degree, i) * std::pow(lambda, i) * std::pow(1 - lambda, degree - i) * pts[i].p;
      const Pose<double> g = bezierAt<TypeParam>(pts, lambda);
      EXPECT_LT((g.p - ref).norm(), 1e-14);
      EXPECT_LT(rotationAngle(g.q), 1e-15);
    }
  }
}

TYPED_TEST(GeometryTest, BezierAboutOneAxisIsClassicalInTheAngle)
{
  std::mt19937 rng(14);
  const Eigen::Vector3d axis = test::randomUnitVector<3>(rng);
  std::vector<double> angles{ 0.3, 1.4, 0.9, 2.1, 2.6 };
  std::vector<Pose<double>> pts;
  for (double a : angles)
    pts.emplace_back(so3Exp<double>(a * axis), Eigen::Vector3d::Zero());
  const int degree = static_cast<int>(angles.size()) - 1;
  for (double lambda : { 0.0, 0.2, 0.5, 0.9, 1.0 })
  {
    double ref = 0.0;
    for (int i = 0; i <= degree; ++i)
      ref += binomial(degree, i) * std::pow(lambda, i) * std::pow(1 - lambda, degree - i) * angles[i];
    const Pose<double> g = bezierAt<TypeParam>(pts, lambda);
    EXPECT_LT(poseDistance(g, Pose<double>(so3Exp<double>(ref * axis), Eigen::Vector3d::Zero())), 1e-14);
  }
}

TYPED_TEST(GeometryTest, BezierEndpointsAndAffineReparameterisation)
{
  std::mt19937 rng(15);
  for (int i = 0; i < 50; ++i)
  {
    const auto pts = randomPolygon(rng, 5);
    const BezierCurve<TypeParam> c(pts, 2.0, 5.0);
    EXPECT_LT(poseDistance(c.value(2.0), pts.front()), 1e-13);
    EXPECT_LT(poseDistance(c.value(5.0), pts.back()), 1e-12);
    for (double t : { 2.3, 3.5, 4.9 })  // Prop. 4.2.2
      EXPECT_LT(poseDistance(c.value(t), bezierAt<TypeParam>(pts, (t - 2.0) / 3.0)), 1e-13);
  }
}

TYPED_TEST(GeometryTest, BezierSymmetry)
{
  std::mt19937 rng(16);
  for (int i = 0; i < 50; ++i)
  {
    auto pts = randomPolygon(rng, 5);
    auto rev = pts;
    std::reverse(rev.begin(), rev.end());
    for (double lambda : { 0.0, 0.15, 0.5, 0.6, 1.0 })  // Prop. 4.2.3
      EXPECT_LT(poseDistance(bezierAt<TypeParam>(pts, lambda), bezierAt<TypeParam>(rev, 1 - lambda)), 1e-12);
  }
}

TYPED_TEST(GeometryTest, BezierGeodesicPrecision)
{
  std::mt19937 rng(17);
  for (int i = 0; i < 50; ++i)
  {
    const Pose<double> g0 = randomPose(rng);
    Vector6<double> xi;
    xi << 0.5 * test::randomUnitVector<3>(rng), test::randomUnitVector<3>(rng);
    // Control points in order along one geodesic (Prop. 4.2.4).
    std::vector<Pose<double>> pts;
    for (double s : { 0.0, 0.3, 1.1, 1.5, 2.0 })
      pts.push_back(TypeParam::exp(g0, Vector6<double>(s * xi)));
    for (double lambda : { 0.1, 0.45, 0.9 })
    {
      const Vector6<double> v = TypeParam::log(g0, bezierAt<TypeParam>(pts, lambda));
      // v is a non-negative multiple of xi
      const double s = v.dot(xi) / xi.squaredNorm();
      EXPECT_GE(s, 0.0);
      EXPECT_LT((v - s * xi).norm(), 1e-12);
    }
  }
}

TYPED_TEST(GeometryTest, LeftInvariance)
{
  std::mt19937 rng(18);
  for (int i = 0; i < 50; ++i)
  {
    const auto pts = randomPolygon(rng, 4);
    const Pose<double> h = randomPose(rng);
    std::vector<Pose<double>> moved;
    for (const auto& p : pts)
      moved.push_back(h * p);
    for (double lambda : { 0.2, 0.5, 0.85 })  // Prop. 4.2.1
      EXPECT_LT(poseDistance(h * bezierAt<TypeParam>(pts, lambda), bezierAt<TypeParam>(moved, lambda)), 1e-12);
  }
}

TEST(Invariance, ScrewIsRightInvariantDoubleGeodesicIsNot)
{
  std::mt19937 rng(19);
  double worst_screw = 0.0;
  double best_double = 1e9;
  for (int i = 0; i < 50; ++i)
  {
    const auto pts = randomPolygon(rng, 4);
    const Pose<double> h(so3Exp<double>(Eigen::Vector3d(0.4, -0.7, 0.2)), Eigen::Vector3d(1.0, 2.0, -0.5));
    std::vector<Pose<double>> moved;
    for (const auto& p : pts)
      moved.push_back(p * h);
    const double lambda = 0.4;
    worst_screw = std::max(worst_screw, poseDistance(bezierAt<ScrewSe3>(pts, lambda) * h,
                                                     bezierAt<ScrewSe3>(moved, lambda)));
    best_double = std::min(best_double, poseDistance(bezierAt<DoubleGeodesicSe3>(pts, lambda) * h,
                                                     bezierAt<DoubleGeodesicSe3>(moved, lambda)));
  }
  EXPECT_LT(worst_screw, 1e-12);  // Cor. 4.2.7: the screw metric is Ad-invariant
  EXPECT_GT(best_double, 1e-3);   // the product metric is not
}

TYPED_TEST(GeometryTest, AnalyticDerivativesMatchCentralDifferences)
{
  std::mt19937 rng(20);
  for (int i = 0; i < 30; ++i)
  {
    const auto pts = randomPolygon(rng, 2 + i % 5);
    const BezierCurve<TypeParam> c(pts, 1.0, 3.0);
    for (double t : { 1.01, 1.7, 2.5, 2.99 })
    {
      const Kinematics a = kinematicsAt(c, t);
      const Kinematics f = test::centralDifferences([&](double s) { return c.value(s); }, t, 1e-3);
      auto rel = [](const Eigen::Vector3d& x, const Eigen::Vector3d& y, double scale) {
        return (x - y).norm() / std::max(1.0, scale);
      };
      EXPECT_LT(rel(a.velocity.linear, f.velocity.linear, a.velocity.linear.norm()), 1e-6);
      EXPECT_LT(rel(a.velocity.angular, f.velocity.angular, a.velocity.angular.norm()), 1e-6);
      EXPECT_LT(rel(a.acceleration.linear, f.acceleration.linear, a.acceleration.linear.norm()), 1e-6);
      EXPECT_LT(rel(a.acceleration.angular, f.acceleration.angular, a.acceleration.angular.norm()), 1e-6);
    }
  }
}

TYPED_TEST(GeometryTest, EndVelocitiesFollowProposition428)
{
  // d/dλ p_n(0) = n g_0 V_0^1 and d/dλ p_n(1) = n g_n V_{n−1}^1 (body velocities), with
  // V_k^1 = Log(g_k, g_{k+1}). For the screw metric the body twist maps to the spatial
  // velocity (ω, ṗ) = (R ω_b, R v_b); for the product metric (ω, ṗ) = (R ω_b, Δp).
  std::mt19937 rng(21);
  for (int i = 0; i < 30; ++i)
  {
    const std::size_t n = 2 + i % 5;
    const auto pts = randomPolygon(rng, n);
    const BezierCurve<TypeParam> c(pts, 0.0, 1.0);
    const int degree = static_cast<int>(n) - 1;
    for (int end = 0; end < 2; ++end)
    {
      const Pose<double>& g = end == 0 ? pts[0] : pts[n - 1];
      const Vector6<double> v = end == 0 ? TypeParam::log(pts[0], pts[1]) : TypeParam::log(pts[n - 2], pts[n - 1]);
      const Kinematics k = kinematicsAt(c, end == 0 ? 0.0 : 1.0, end == 0 ? Side::kRight : Side::kLeft);
      const Eigen::Matrix3d r = g.q.toRotationMatrix();
      const Eigen::Vector3d omega = degree * (r * v.head<3>());
      const Eigen::Vector3d pdot =
          std::is_same<TypeParam, ScrewSe3>::value ? Eigen::Vector3d(degree * (r * v.tail<3>())) :
                                                     Eigen::Vector3d(degree * v.tail<3>());
      EXPECT_LT((k.velocity.angular - omega).norm(), 1e-12 * std::max(1.0, omega.norm()));
      EXPECT_LT((k.velocity.linear - pdot).norm(), 1e-12 * std::max(1.0, pdot.norm()));
    }
  }
}

TEST(Subdivision, ExactInEuclideanSpace)
{
  std::mt19937 rng(22);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Eigen::VectorXd> pts;
  for (int i = 0; i < 5; ++i)
    pts.push_back(Eigen::Vector3d(n(rng), n(rng), n(rng)));
  std::vector<Eigen::VectorXd> left, right;
  subdivideBezier<Euclidean>(pts, 0.35, &left, &right);
  const auto logs = polygonLogs<Euclidean>(pts, "p");
  const auto left_logs = polygonLogs<Euclidean>(left, "p");
  const auto right_logs = polygonLogs<Euclidean>(right, "p");
  for (double s : { 0.0, 0.3, 0.7, 1.0 })
  {
    EXPECT_LT((deCasteljau<Euclidean>(left, left_logs, s) - deCasteljau<Euclidean>(pts, logs, 0.35 * s)).norm(), 1e-14);
    EXPECT_LT((deCasteljau<Euclidean>(right, right_logs, s) - deCasteljau<Euclidean>(pts, logs, 0.35 + 0.65 * s)).norm(),
              1e-14);
  }
}

TYPED_TEST(GeometryTest, SubdivisionIsExactAtTheSplitAndCloseElsewhere)
{
  // On a curved group the halves' de Casteljau curves only approximate the original
  // (the same non-commutativity as the thesis' Menelaus question for knot insertion):
  // they agree at both ends and at the split, with a small deviation inside.
  std::mt19937 rng(22);
  for (int i = 0; i < 20; ++i)
  {
    const auto pts = randomPolygon(rng, 4, 0.5);
    std::vector<Pose<double>> left, right;
    subdivideBezier<TypeParam>(pts, 0.35, &left, &right);
    EXPECT_LT(poseDistance(left.back(), bezierAt<TypeParam>(pts, 0.35)), 1e-12);
    EXPECT_LT(poseDistance(right.front(), bezierAt<TypeParam>(pts, 0.35)), 1e-12);
    EXPECT_LT(poseDistance(left.front(), pts.front()), 1e-15);
    EXPECT_LT(poseDistance(right.back(), pts.back()), 1e-15);
    for (double s : { 0.3, 0.7 })
    {
      EXPECT_LT(poseDistance(bezierAt<TypeParam>(left, s), bezierAt<TypeParam>(pts, 0.35 * s)), 1e-2);
      EXPECT_LT(poseDistance(bezierAt<TypeParam>(right, s), bezierAt<TypeParam>(pts, 0.35 + 0.65 * s)), 1e-2);
    }
  }
}

TYPED_TEST(GeometryTest, PiecewiseGeodesicPassesThroughWaypoints)
{
  std::mt19937 rng(23);
  const auto pts = randomPolygon(rng, 6);
  const std::vector<double> times{ 0.0, 0.5, 1.7, 2.0, 3.1, 4.0 };
  const PiecewiseGeodesic<TypeParam> c(pts, times);
  for (std::size_t i = 0; i < pts.size(); ++i)
    EXPECT_LT(poseDistance(c.value(times[i]), pts[i]), 1e-12);
  EXPECT_LT(poseDistance(c.value(1.1), geodesic<TypeParam>(pts[1], pts[2], 0.5)), 1e-12);
}

TEST(Geodesic, AntipodalWaypointsAreNamed)
{
  std::vector<Pose<double>> pts(3);
  pts[2].q = Quaternion<double>(0.0, 0.0, 0.0, 1.0);  // π about z from pts[1]
  try
  {
    PiecewiseGeodesic<ScrewSe3>(pts, { 0.0, 1.0, 2.0 });
    FAIL() << "expected NonUniqueGeodesicError";
  }
  catch (const NonUniqueGeodesicError& e)
  {
    EXPECT_NE(std::string(e.what()).find("waypoints[1] and waypoints[2]"), std::string::npos) << e.what();
  }
}
