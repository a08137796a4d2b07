// Corner blending of piecewise_geodesic (corner_blend.h): the classical Euclidean
// constructions for pure translations and for rotations about one axis, the polyline outside
// the blends (same poses at the same times), the ball of radius r_i, C² joins from one-sided
// jets, clamping to half legs, finite differences, hard corners (collinear, reversal, tiny
// radius), time-optimal timing through blends and the request's validation. Both SE(3) geometries.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "se3_interpolation/curves/corner_blend.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "test_utils.h"

using namespace se3_interpolation;
using test::randomPolygon;

namespace
{
template <class G>
class CornerBlendTest : public ::testing::Test
{
};
using SE3Geometries = ::testing::Types<ScrewSe3, DoubleGeodesicSe3>;
TYPED_TEST_SUITE(CornerBlendTest, SE3Geometries);

/// Test-side chord distance sqrt(|Δp|² + (ρ θ)²), θ = 2 atan2(|vec|, |w|) of q_a* q_b.
double chord(const Pose<double>& a, const Pose<double>& b, double rho)
{
  const Eigen::Quaterniond d = a.q.conjugate() * b.q;
  const double theta = 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
  return std::sqrt((a.p - b.p).squaredNorm() + rho * rho * theta * theta);
}

double binomial(int n, int k)
{
  double r = 1.0;
  for (int i = 1; i <= k; ++i)
    r = r * (n - k + i) / i;
  return r;
}

/// Σ C(4, k) (1 − u)^{4−k} u^k c_k with std::pow: the Euclidean quartic Bézier curve.
Eigen::Vector3d quarticBezier(const std::vector<Eigen::Vector3d>& c, double u)
{
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (int k = 0; k <= 4; ++k)
    s += c[k] * binomial(4, k) * std::pow(1.0 - u, 4 - k) * std::pow(u, k);
  return s;
}

/// ψ⁻¹ by bisection: t − t_start = 2τ_in λ + 2(τ_out − τ_in)(λ³ − λ⁴/2).
double bisectBlendParameter(double u, double tau_in, double tau_out)
{
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 200; ++i)
  {
    const double m = 0.5 * (lo + hi);
    const double psi = 2.0 * tau_in * m + 2.0 * (tau_out - tau_in) * (m * m * m - 0.5 * m * m * m * m);
    (psi < u ? lo : hi) = m;
  }
  return 0.5 * (lo + hi);
}

double rel(const Eigen::Vector3d& x, const Eigen::Vector3d& y, double scale)
{
  return (x - y).norm() / std::max(1.0, scale);
}

bool insideSomeBlend(const std::vector<CornerBlendZone>& zones, double t, double margin)
{
  for (const CornerBlendZone& z : zones)
    if (t > z.start_time - margin && t < z.end_time + margin)
      return true;
  return false;
}

std::vector<Pose<double>> translations(const std::vector<Eigen::Vector3d>& p)
{
  std::vector<Pose<double>> x;
  for (const auto& v : p)
    x.emplace_back(Quaternion<double>::Identity(), v);
  return x;
}

TrajectoryRequest blendedRequest(double radius)
{
  TrajectoryRequest r;
  r.curve = "piecewise_geodesic";
  for (int i = 0; i < 4; ++i)
    r.waypoints.emplace_back(Quaternion<double>(so3Exp<double>(Eigen::Vector3d(0.0, 0.0, 0.4 * i))),
                             Eigen::Vector3d(i % 2, i, 0.0));
  r.blend_radius = radius;
  return r;
}

void expectBlendRadiusError(const TrajectoryRequest& r)
{
  try
  {
    generate(r, test::unhurriedLimits());
    FAIL() << "expected InvalidInputError";
  }
  catch (const InvalidInputError& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("blend_radius", 0), 0u) << e.what();
  }
}
}  // namespace

TYPED_TEST(CornerBlendTest, PureTranslationsGiveTheEuclideanQuarticBezier)
{
  // Classical construction in R^3: on [t_i − τ_in, t_i + τ_out] the quartic Bézier curve with
  // control points a, (a + x)/2, x, (x + b)/2, b, where a and b are the points at distance r_i
  // from x on the two straight legs and τ = r_i / (leg speed); λ = ψ⁻¹(t).
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial)
  {
    std::vector<Eigen::Vector3d> p;
    std::vector<double> times{ 0.0 };
    for (int i = 0; i < 5; ++i)
    {
      p.emplace_back(n(rng), n(rng), n(rng));
      if (i > 0)
        times.push_back(times.back() + 0.2 + std::uniform_real_distribution<double>(0.0, 3.0)(rng));
    }
    const double radius = 0.1 + 0.6 * std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    const CornerBlendedGeodesic<TypeParam> c(translations(p), times, radius, 1.0);
    for (std::size_t i = 1; i + 1 < p.size(); ++i)
    {
      const double d_in = (p[i] - p[i - 1]).norm(), d_out = (p[i + 1] - p[i]).norm();
      const double r = std::min({ radius, d_in / 2.0, d_out / 2.0 });
      EXPECT_NEAR(c.radii()[i], r, 1e-15);
      const Eigen::Vector3d a = p[i] + (r / d_in) * (p[i - 1] - p[i]);
      const Eigen::Vector3d b = p[i] + (r / d_out) * (p[i + 1] - p[i]);
      const std::vector<Eigen::Vector3d> ctrl{ a, 0.5 * (a + p[i]), p[i], 0.5 * (p[i] + b), b };
      const double tau_in = r / d_in * (times[i] - times[i - 1]);
      const double tau_out = r / d_out * (times[i + 1] - times[i]);
      for (double f : { 0.0, 0.1, 0.37, 0.5, 0.81, 1.0 })
      {
        const double t = times[i] - tau_in + f * (tau_in + tau_out);
        const double lambda = bisectBlendParameter(t - (times[i] - tau_in), tau_in, tau_out);
        const Pose<double> x = c.value(t);
        EXPECT_LT((x.p - quarticBezier(ctrl, lambda)).norm(), 1e-12) << "corner " << i << " f " << f;
        EXPECT_LT(x.q.vec().norm(), 1e-15);
      }
    }
  }
}

TYPED_TEST(CornerBlendTest, EqualLegSpeedsGiveTheQuinticHermiteWithZeroEndAccelerations)
{
  // With one speed on both legs (chord timing) the blend is the quintic polynomial with the
  // legs' positions and velocities and zero accelerations at both ends (quintic Hermite basis).
  const std::vector<Eigen::Vector3d> p{ { 0, 0, 0 }, { 2, 0, 0 }, { 2, 3, 1 } };
  const double speed = 1.7;
  std::vector<double> times{ 0.0 };
  for (std::size_t i = 1; i < p.size(); ++i)
    times.push_back(times.back() + (p[i] - p[i - 1]).norm() / speed);
  const double r = 0.6;
  const CornerBlendedGeodesic<TypeParam> c(translations(p), times, r, 1.0);
  const Eigen::Vector3d v_in = speed * (p[1] - p[0]).normalized(), v_out = speed * (p[2] - p[1]).normalized();
  const double tau = r / speed, t0 = times[1] - tau, h = 2.0 * tau;
  const Eigen::Vector3d a = p[1] - tau * v_in, b = p[1] + tau * v_out;
  for (double f : { 0.05, 0.3, 0.5, 0.66, 0.95 })
  {
    const double u = f;
    const double h00 = 1 - 10 * std::pow(u, 3) + 15 * std::pow(u, 4) - 6 * std::pow(u, 5);
    const double h01 = 1 - h00;
    const double h10 = u - 6 * std::pow(u, 3) + 8 * std::pow(u, 4) - 3 * std::pow(u, 5);
    const double h11 = -4 * std::pow(u, 3) + 7 * std::pow(u, 4) - 3 * std::pow(u, 5);
    const Eigen::Vector3d expected = h00 * a + h01 * b + h * (h10 * v_in + h11 * v_out);
    EXPECT_LT((c.value(t0 + f * h).p - expected).norm(), 1e-12) << f;
  }
}

TYPED_TEST(CornerBlendTest, RotationAboutOneAxisIsTheQuarticBezierInTheAngle)
{
  // Abelian case: rotations about one fixed axis (no translation); the chord distance is ρ|Δθ|.
  const std::vector<double> angle{ 0.0, 1.2, 0.5, 2.1 };
  const std::vector<double> times{ 0.0, 1.0, 3.5, 4.0 };
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();
  std::vector<Pose<double>> x;
  for (double a : angle)
    x.emplace_back(so3Exp<double>(a * axis), Eigen::Vector3d::Zero());
  const double rho = 0.8, radius = 0.3;
  const CornerBlendedGeodesic<TypeParam> c(x, times, radius, rho);
  for (std::size_t i = 1; i + 1 < x.size(); ++i)
  {
    const double d_in = rho * std::abs(angle[i] - angle[i - 1]), d_out = rho * std::abs(angle[i + 1] - angle[i]);
    const double r = std::min({ radius, d_in / 2.0, d_out / 2.0 });
    const double s_in = r / d_in, s_out = r / d_out;
    const double a = angle[i] + s_in * (angle[i - 1] - angle[i]), b = angle[i] + s_out * (angle[i + 1] - angle[i]);
    const std::vector<Eigen::Vector3d> ctrl{ Eigen::Vector3d(a, 0, 0), Eigen::Vector3d(0.5 * (a + angle[i]), 0, 0),
                                             Eigen::Vector3d(angle[i], 0, 0),
                                             Eigen::Vector3d(0.5 * (angle[i] + b), 0, 0), Eigen::Vector3d(b, 0, 0) };
    const double tau_in = s_in * (times[i] - times[i - 1]), tau_out = s_out * (times[i + 1] - times[i]);
    for (double f : { 0.2, 0.5, 0.9 })
    {
      const double t = times[i] - tau_in + f * (tau_in + tau_out);
      const double theta = quarticBezier(ctrl, bisectBlendParameter(t - (times[i] - tau_in), tau_in, tau_out)).x();
      const Pose<double> got = c.value(t);
      EXPECT_LT(got.p.norm(), 1e-14);
      EXPECT_LT(test::poseDistance(got, Pose<double>(so3Exp<double>(theta * axis), Eigen::Vector3d::Zero())), 1e-12);
    }
  }
}

TYPED_TEST(CornerBlendTest, OutsideTheBallsThePathAndTimingAreThePolylines)
{
  std::mt19937 rng(2);
  for (int trial = 0; trial < 20; ++trial)
  {
    const auto x = randomPolygon(rng, 6, 1.2);
    std::vector<double> times{ 0.0 };
    for (int i = 1; i < 6; ++i)
      times.push_back(times.back() + 0.1 + std::uniform_real_distribution<double>(0.0, 2.0)(rng));
    const double rho = trial % 2 == 0 ? 1.0 : 0.3;
    const CornerBlendedGeodesic<TypeParam> c(x, times, 0.4, rho);
    const PiecewiseGeodesic<TypeParam> polyline(x, times);
    const auto zones = c.zones();
    EXPECT_EQ(zones.size(), 4u);
    for (const CornerBlendZone& z : zones)
    {
      // The blend's ends are where the polyline itself is at distance r_i from the corner.
      EXPECT_NEAR(chord(polyline.value(z.start_time), x[z.corner], rho), z.radius, 1e-12);
      EXPECT_NEAR(chord(polyline.value(z.end_time), x[z.corner], rho), z.radius, 1e-12);
      EXPECT_LT(z.start_time, times[z.corner]);
      EXPECT_GT(z.end_time, times[z.corner]);
    }
    int outside = 0;
    for (int k = 0; k <= 2000; ++k)
    {
      const double t = times.back() * k / 2000.0;
      if (insideSomeBlend(zones, t, 0.0))
        continue;
      ++outside;
      EXPECT_LT(test::poseDistance(c.value(t), polyline.value(t)), 1e-12) << t;
    }
    EXPECT_GT(outside, 100);
    // The first and last waypoints are still passed through.
    EXPECT_LT(test::poseDistance(c.value(times.front()), x.front()), 1e-15);
    EXPECT_LT(test::poseDistance(c.value(times.back()), x.back()), 1e-12);
  }
}

TYPED_TEST(CornerBlendTest, InsideTheBlendTheCornerIsWithinTheRadius)
{
  // Proven for double_geodesic (the triangle inequality in the chart at the corner, corner_blend.h),
  // checked here for screw as well: legs with up to 3.1 rad of rotation, translations from 1 cm to
  // 10 m, rho from 0.01 to 10 (and 2·10⁴ such trials in a one-off run).
  std::mt19937 rng(3);
  double worst = 0.0;
  for (int trial = 0; trial < 160; ++trial)
  {
    const double scale = std::vector<double>{ 0.01, 0.1, 1.0, 10.0 }[trial % 4];
    const double rho = std::vector<double>{ 0.01, 0.1, 1.0, 10.0 }[(trial / 4) % 4];
    const double step = std::uniform_real_distribution<double>(0.1, 3.1)(rng);
    std::vector<Pose<double>> x{ test::randomPose(rng, 3.0, scale) };
    for (int i = 1; i < 5; ++i)
      x.push_back(x.back() * test::randomPose(rng, step, scale));
    const std::vector<double> times{ 0.0, 1.0, 1.3, 4.0, 4.5 };
    // Clamped to half legs everywhere, or a radius smaller than most legs.
    const CornerBlendedGeodesic<TypeParam> c(x, times, trial % 3 == 0 ? 0.3 * scale : 1e6, rho);
    for (const CornerBlendZone& z : c.zones())
    {
      for (int k = 0; k <= 200; ++k)
      {
        const double t = z.start_time + (z.end_time - z.start_time) * k / 200.0;
        const double d = chord(c.value(t), x[z.corner], rho);
        worst = std::max(worst, d / z.radius);
        // The ends lie on the legs, evaluated in absolute coordinates: allow their rounding.
        EXPECT_LE(d, z.radius * (1.0 + (k == 0 || k == 200 ? 1e-9 : 1e-12)))
            << "trial " << trial << " corner " << z.corner << " k " << k;
      }
    }
  }
  EXPECT_GT(worst, 0.999);  // the ends are on the sphere of radius r_i
}

TYPED_TEST(CornerBlendTest, JoinsAreC2FromBothSides)
{
  std::mt19937 rng(4);
  for (int trial = 0; trial < 20; ++trial)
  {
    const auto x = randomPolygon(rng, 5, 1.5);
    std::vector<double> times{ 0.0 };
    for (int i = 1; i < 5; ++i)
      times.push_back(times.back() + 0.1 + std::uniform_real_distribution<double>(0.0, 3.0)(rng));
    const CornerBlendedGeodesic<TypeParam> c(x, times, trial % 2 == 0 ? 0.3 : 1e3, 0.7);
    for (const CornerBlendZone& z : c.zones())
      for (double t : { z.start_time, z.end_time })
      {
        const Kinematics l = kinematicsAt(c, t, Side::kLeft);
        const Kinematics r = kinematicsAt(c, t, Side::kRight);
        const double v = std::max(l.velocity.linear.norm(), l.velocity.angular.norm());
        EXPECT_LT(test::poseDistance(l.pose, r.pose), 1e-12);
        EXPECT_LT(rel(l.velocity.linear, r.velocity.linear, v), 1e-9);
        EXPECT_LT(rel(l.velocity.angular, r.velocity.angular, v), 1e-9);
        EXPECT_LT(rel(l.acceleration.linear, r.acceleration.linear, v * v), 1e-9);
        EXPECT_LT(rel(l.acceleration.angular, r.acceleration.angular, v * v), 1e-9);
      }
    // The sharp polyline, for contrast, has velocity jumps at its corners.
    const PiecewiseGeodesic<TypeParam> polyline(x, times);
    EXPECT_GT((kinematicsAt(polyline, times[2], Side::kLeft).velocity.linear -
               kinematicsAt(polyline, times[2], Side::kRight).velocity.linear)
                  .norm(),
              1e-3);
  }
}

TYPED_TEST(CornerBlendTest, RadiiClampToHalfOfEachAdjacentLeg)
{
  const std::vector<Eigen::Vector3d> p{ { 0, 0, 0 }, { 4, 0, 0 }, { 4, 1, 0 }, { 0, 1, 0 }, { 0, 7, 0 } };
  const std::vector<double> times{ 0.0, 2.0, 3.0, 5.0, 6.0 };
  const CornerBlendedGeodesic<TypeParam> c(translations(p), times, 1.5, 1.0);
  const std::vector<double> expected{ 0.0, 0.5, 0.5, 1.5, 0.0 };
  for (std::size_t i = 0; i < p.size(); ++i)
    EXPECT_NEAR(c.radii()[i], expected[i], 1e-15) << i;
  // Corners 1 and 2 both take half of the 1 m leg: their blends meet at its middle, C².
  const auto zones = c.zones();
  ASSERT_EQ(zones.size(), 3u);
  EXPECT_NEAR(zones[0].end_time, 2.5, 1e-14);
  EXPECT_NEAR(zones[1].start_time, 2.5, 1e-14);
  EXPECT_NEAR(zones[2].start_time, 5.0 - 1.5 / 4.0 * 2.0, 1e-14);
  const Kinematics l = kinematicsAt(c, 2.5, Side::kLeft), r = kinematicsAt(c, 2.5, Side::kRight);
  EXPECT_LT((l.pose.p - Eigen::Vector3d(4.0, 0.5, 0.0)).norm(), 1e-14);
  EXPECT_LT((l.velocity.linear - Eigen::Vector3d(0.0, 1.0, 0.0)).norm(), 1e-12);
  EXPECT_LT((r.velocity.linear - l.velocity.linear).norm(), 1e-12);
  EXPECT_LT(l.acceleration.linear.norm() + r.acceleration.linear.norm(), 1e-11);
}

TYPED_TEST(CornerBlendTest, AnalyticDerivativesMatchFiniteDifferences)
{
  std::mt19937 rng(5);
  for (int trial = 0; trial < 20; ++trial)
  {
    const auto x = randomPolygon(rng, 4, 1.3);
    const std::vector<double> times{ 0.0, 0.7, 2.9, 3.4 };
    const CornerBlendedGeodesic<TypeParam> c(x, times, 0.5, 1.0);
    for (const CornerBlendZone& z : c.zones())
      for (double f : { 0.1, 0.45, 0.8 })
      {
        const double t = z.start_time + f * (z.end_time - z.start_time);
        const Kinematics a = kinematicsAt(c, t);
        const Kinematics d = test::centralDifferences([&](double s) { return c.value(s); }, t, 1e-4);
        EXPECT_LT(rel(a.velocity.linear, d.velocity.linear, a.velocity.linear.norm()), 1e-6);
        EXPECT_LT(rel(a.velocity.angular, d.velocity.angular, a.velocity.angular.norm()), 1e-6);
        EXPECT_LT(rel(a.acceleration.linear, d.acceleration.linear, a.acceleration.linear.norm()), 1e-6);
        EXPECT_LT(rel(a.acceleration.angular, d.acceleration.angular, a.acceleration.angular.norm()), 1e-6);
      }
  }
}

/// x · exp(x, Σ_k B_k(λ) Log(x, c_k)): the quartic Bézier curve of the five control points in the
/// exponential chart at x (Bernstein polynomials B_k by std::pow), at a double or a jet λ.
template <class G, class S>
Pose<S> quarticInChart(const Pose<double>& x, const std::vector<Pose<double>>& control, const S& lambda)
{
  Vector6<S> log = Vector6<S>::Zero();
  for (int k = 0; k <= 4; ++k)
  {
    S weight(binomial(4, k));
    for (int j = 0; j < k; ++j)
      weight = weight * lambda;
    for (int j = 0; j < 4 - k; ++j)
      weight = weight * (S(1.0) - lambda);
    const Vector6<double> lk = G::log(x, control[static_cast<std::size_t>(k)]);
    for (int i = 0; i < 6; ++i)
      log[i] = log[i] + weight * lk[i];
  }
  return G::exp(x.cast<S>(), log);
}

TYPED_TEST(CornerBlendTest, GeneralCornersAreTheQuarticBezierInTheChartAtTheCorner)
{
  // The blend against x_i exp(x_i, Σ B_k(λ) Log(x_i, c_k)) for c_0 = a_i, c_1 = γ(a_i, x_i; ½),
  // c_2 = x_i, c_3 = γ(x_i, b_i; ½), c_4 = b_i (a_i, b_i the curve at the blend's ends), at
  // λ = ψ⁻¹(t) (bisection): values, and the jets at the jet λ(t) (dλ/dt = 1/ψ′,
  // d²λ/dt² = −ψ″/ψ′³), on random corners between uneven times.
  using G = TypeParam;
  std::mt19937 rng(21);
  for (int trial = 0; trial < 20; ++trial)
  {
    const auto x = randomPolygon(rng, 5, 1.2);
    const std::vector<double> times{ 0.0, 0.02, 2.9, 3.4, 40.0 };
    const CornerBlendedGeodesic<G> c(x, times, 0.6, 0.8);
    ASSERT_FALSE(c.zones().empty());
    for (const CornerBlendZone& z : c.zones())
    {
      const std::size_t i = z.corner;
      const Pose<double> a = c.value(z.start_time);
      const Pose<double> b = c.value(z.end_time);
      const std::vector<Pose<double>> control{ a, geodesic<G>(a, x[i], 0.5), x[i], geodesic<G>(x[i], b, 0.5), b };
      const double tau_in = times[i] - z.start_time;
      const double tau_out = z.end_time - times[i];
      for (double f : { 0.0, 0.03, 0.3, 0.5, 0.77, 0.999 })
      {
        const double t = z.start_time + f * (z.end_time - z.start_time);
        const double l = bisectBlendParameter(t - z.start_time, tau_in, tau_out);
        const double dpsi = 2.0 * tau_in + 2.0 * (tau_out - tau_in) * (3.0 * l * l - 2.0 * l * l * l);
        const double ddpsi = 2.0 * (tau_out - tau_in) * (6.0 * l - 6.0 * l * l);
        Jet<2> lambda(l);
        lambda.coefficient(1) = 1.0 / dpsi;
        lambda.coefficient(2) = -0.5 * ddpsi / (dpsi * dpsi * dpsi);
        Pose<Jet<2>> ref = quarticInChart<G>(x[i], control, lambda);
        const Pose<Jet<2>> got = c.jet(Jet<2>::variable(t), Side::kRight);
        // (q and −q are one rotation: compare with the sign of the curve's quaternion.)
        double dot = 0.0;
        for (int j = 0; j < 4; ++j)
          dot += got.q.coeffs()[j].value() * ref.q.coeffs()[j].value();
        if (dot < 0.0)
          for (int j = 0; j < 4; ++j)
            ref.q.coeffs()[j] = -ref.q.coeffs()[j];
        const Pose<double> value = quarticInChart<G>(x[i], control, l);
        EXPECT_LT(test::poseDistance(c.value(t), value), 1e-12) << "trial " << trial << " corner " << i << " f " << f;
        for (int k = 0; k <= 2; ++k)
        {
          const double scale = 1.0 + (k == 0 ? 0.0 : std::abs(lambda.coefficient(1)) + std::abs(lambda.coefficient(2)));
          for (int j = 0; j < 4; ++j)
            EXPECT_NEAR(got.q.coeffs()[j].coefficient(k), ref.q.coeffs()[j].coefficient(k), 1e-11 * scale)
                << "trial " << trial << " corner " << i << " f " << f << " order " << k;
          for (int j = 0; j < 3; ++j)
            EXPECT_NEAR(got.p[j].coefficient(k), ref.p[j].coefficient(k), 1e-11 * scale)
                << "trial " << trial << " corner " << i << " f " << f << " order " << k;
        }
      }
    }
  }
}

TYPED_TEST(CornerBlendTest, CollinearCornerAtOneSpeedIsTheGeodesicItself)
{
  // x_{i−1}, x_i, x_{i+1} on one geodesic, one speed: the blend's control points are equally
  // spaced on that geodesic, so the blend is the geodesic (geodesic precision), at the same times.
  Vector6<double> xi;
  xi << 0.3, -0.2, 0.5, 1.0, 0.4, -0.7;
  const Pose<double> x0(so3Exp<double>(Eigen::Vector3d(0.4, 0.1, -0.3)), Eigen::Vector3d(1.0, 2.0, 3.0));
  const Pose<double> x1 = TypeParam::exp(x0, xi);
  const Pose<double> x2 = TypeParam::exp(x1, TypeParam::log(x0, x1));
  const CornerBlendedGeodesic<TypeParam> c({ x0, x1, x2 }, { 0.0, 1.0, 2.0 }, 0.5, 1.0);
  ASSERT_EQ(c.zones().size(), 1u);
  for (double t : { 0.8, 0.95, 1.0, 1.1, 1.3 })
  {
    EXPECT_LT(test::poseDistance(c.value(t), geodesic<TypeParam>(x0, x2, t / 2.0)), 1e-12) << t;
    const Kinematics k = kinematicsAt(c, t);
    EXPECT_LT(k.acceleration.angular.norm(), 1e-10);
  }
  // At two speeds the blend still follows the line (pure translation) and moves forward.
  const std::vector<Eigen::Vector3d> p{ { 0, 0, 0 }, { 1, 1, 0 }, { 3, 3, 0 } };
  const CornerBlendedGeodesic<TypeParam> slow_fast(translations(p), { 0.0, 2.0, 2.5 }, 0.5, 1.0);
  const CornerBlendZone z = slow_fast.zones().at(0);
  for (int k = 0; k <= 50; ++k)
  {
    const Kinematics s = kinematicsAt(slow_fast, z.start_time + (z.end_time - z.start_time) * k / 50.0);
    EXPECT_LT(std::abs(s.pose.p.x() - s.pose.p.y()), 1e-14);
    EXPECT_GT(s.velocity.linear.x(), 0.0);
  }
}

TYPED_TEST(CornerBlendTest, ReversalCornerTurnsBackInsideTheBall)
{
  // x_{i+1} = x_{i−1}: a 180-degree reversal. The blend stays on the leg's line (translation)
  // and rotation path, turns at rest at its middle, and stays finite and within r_i.
  const Pose<double> x0(so3Exp<double>(Eigen::Vector3d(0.1, 0.2, 0.3)), Eigen::Vector3d(0.0, 0.0, 0.0));
  const Pose<double> x1(so3Exp<double>(Eigen::Vector3d(0.1, 0.2, 1.1)), Eigen::Vector3d(2.0, 1.0, 0.0));
  const CornerBlendedGeodesic<TypeParam> c({ x0, x1, x0 }, { 0.0, 1.0, 2.0 }, 0.4, 1.0);
  const CornerBlendZone z = c.zones().at(0);
  EXPECT_NEAR(z.start_time + z.end_time, 2.0, 1e-14);
  for (int k = 0; k <= 100; ++k)
  {
    const double t = z.start_time + (z.end_time - z.start_time) * k / 100.0;
    const Kinematics s = kinematicsAt(c, t);
    EXPECT_LE(chord(s.pose, x1, 1.0), z.radius * (1.0 + 1e-12));
    for (double v : { s.velocity.linear.norm(), s.acceleration.linear.norm(), s.acceleration.angular.norm() })
      EXPECT_TRUE(std::isfinite(v));
    // Symmetric in time about the corner.
    EXPECT_LT(test::poseDistance(s.pose, c.value(2.0 - t)), 1e-12);
  }
  const Kinematics turn = kinematicsAt(c, 1.0);
  EXPECT_LT(turn.velocity.linear.norm() + turn.velocity.angular.norm(), 1e-12);
  EXPECT_GT(chord(turn.pose, x1, 1.0), 0.0);
  EXPECT_LT(chord(turn.pose, x1, 1.0), z.radius);
}

TYPED_TEST(CornerBlendTest, TinyRadiusKeepsFullRelativePrecision)
{
  std::mt19937 rng(6);
  const auto x = randomPolygon(rng, 3, 1.0);
  const std::vector<double> times{ 0.0, 1.0, 2.5 };
  const double r = 1e-12;
  const CornerBlendedGeodesic<TypeParam> c(x, times, r, 1.0);
  const CornerBlendZone z = c.zones().at(0);
  EXPECT_DOUBLE_EQ(z.radius, r);
  double peak = 0.0;
  for (int k = 0; k <= 100; ++k)
  {
    const double t = z.start_time + (z.end_time - z.start_time) * k / 100.0;
    const Kinematics s = kinematicsAt(c, t);
    // The legs are evaluated in absolute coordinates: their rounding is an ulp of |p|.
    EXPECT_LE(chord(s.pose, x[1], 1.0), r + 1e-15 * (1.0 + x[1].p.norm()));
    EXPECT_TRUE(std::isfinite(s.acceleration.linear.norm()) && std::isfinite(s.acceleration.angular.norm()));
    peak = std::max(peak, s.acceleration.linear.norm() + s.acceleration.angular.norm());
  }
  EXPECT_GT(peak, 1e9);  // turning within 1e-12 m takes a huge acceleration: a real blend
  for (double t : { z.start_time, z.end_time })
  {
    const Kinematics l = kinematicsAt(c, t, Side::kLeft), rr = kinematicsAt(c, t, Side::kRight);
    const double v = std::max(l.velocity.linear.norm(), l.velocity.angular.norm());
    EXPECT_LT(rel(l.velocity.linear, rr.velocity.linear, v), 1e-9);
    EXPECT_LT(rel(l.velocity.angular, rr.velocity.angular, v), 1e-9);
    // The legs' acceleration is zero; the blend's is zero at its ends relative to its peak.
    EXPECT_LT(rr.acceleration.linear.norm() + l.acceleration.linear.norm(), 1e-9 * peak);
  }
}

TYPED_TEST(CornerBlendTest, DwellAndZeroRadiusLeaveCornersSharp)
{
  std::mt19937 rng(7);
  auto x = randomPolygon(rng, 5, 1.0);
  x[3] = x[2];  // dwell: a zero-length leg leaves both its corners sharp
  const std::vector<double> times{ 0.0, 1.0, 2.0, 3.0, 4.0 };
  const CornerBlendedGeodesic<TypeParam> c(x, times, 0.2, 1.0);
  const std::vector<double> r = c.radii();
  EXPECT_GT(r[1], 0.0);
  EXPECT_EQ(r[2], 0.0);
  EXPECT_EQ(r[3], 0.0);
  EXPECT_LT(test::poseDistance(c.value(2.5), x[2]), 1e-15);
  const CornerBlendedGeodesic<TypeParam> sharp(x, times, 0.0, 1.0);
  const PiecewiseGeodesic<TypeParam> polyline(x, times);
  for (double t : { 0.3, 1.0, 1.7, 3.9 })
    EXPECT_LT(test::poseDistance(sharp.value(t), polyline.value(t)), 1e-15);
}

TEST(CornerBlendRequest, PlannerReportsRadiiAndZeroIsThePolyline)
{
  TrajectoryRequest r = blendedRequest(0.3);
  r.geometry = "screw";
  r.sample_count = 200;
  const TrajectoryResult blended = generate(r, test::unhurriedLimits());
  ASSERT_EQ(blended.blend_radii.size(), 4u);
  EXPECT_EQ(blended.blend_radii[0], 0.0);
  EXPECT_NEAR(blended.blend_radii[1], 0.3, 1e-15);
  EXPECT_NEAR(blended.blend_radii[2], 0.3, 1e-15);
  EXPECT_EQ(blended.blend_radii[3], 0.0);
  r.blend_radius = 0.0;
  const TrajectoryResult sharp = generate(r, test::unhurriedLimits());
  EXPECT_TRUE(sharp.blend_radii.empty());
  EXPECT_LT(blended.figures.length, sharp.figures.length);  // corners cut
  EXPECT_NEAR(blended.duration, sharp.duration, 1e-12);
  EXPECT_LT(test::poseDistance(blended.samples.back().pose, sharp.samples.back().pose), 1e-12);
}

TEST(CornerBlendRequest, BadRadiusIsAnErrorNamingTheField)
{
  expectBlendRadiusError(blendedRequest(-0.1));
  expectBlendRadiusError(blendedRequest(std::numeric_limits<double>::quiet_NaN()));
  expectBlendRadiusError(blendedRequest(std::numeric_limits<double>::infinity()));
  TrajectoryRequest other = blendedRequest(0.2);
  other.curve = "interpolating";
  expectBlendRadiusError(other);
  other.curve = "bezier";
  expectBlendRadiusError(other);
}

TYPED_TEST(CornerBlendTest, TimeOptimalFliesThroughBlendedCorners)
{
  // A zigzag with turns in both channels. Sharp corners are velocity corners: TOPP-RA stops
  // there. Blended corners are C2: the motion keeps moving through them and finishes sooner.
  std::vector<Pose<double>> x;
  for (int i = 0; i < 5; ++i)
    x.emplace_back(so3Exp<double>(Eigen::Vector3d(0.0, 0.3 * (i % 2), 0.5 * i)), Eigen::Vector3d(i, i % 2, 0.0));
  const std::vector<double> times{ 0.0, 1.0, 2.0, 3.0, 4.0 };
  timing::RateBounds bounds;
  bounds.velocity = { 1.0, 1.0 };
  bounds.acceleration = { 2.0, 2.0 };
  auto blended_path = std::make_shared<const CornerBlendedGeodesic<TypeParam>>(x, times, 0.3, 1.0);
  auto sharp_path = std::make_shared<const PiecewiseGeodesic<TypeParam>>(x, times);
  const auto blended = timing::makeTimeOptimalCurve<TypeParam>(blended_path, bounds);
  const auto sharp = timing::makeTimeOptimalCurve<TypeParam>(sharp_path, bounds);
  const double d_blended = blended->endTime() - blended->startTime();
  const double d_sharp = sharp->endTime() - sharp->startTime();
  EXPECT_LT(d_blended, 0.9 * d_sharp) << d_blended << " vs " << d_sharp;
  for (std::size_t i = 1; i + 1 < x.size(); ++i)  // the sharp motion is at rest at each corner
  {
    const Kinematics k = kinematicsAt(*sharp, sharp->profile().timeAt(times[i]));
    EXPECT_LT(k.velocity.linear.norm() + k.velocity.angular.norm(), 1e-9) << i;
  }
  const auto zones = blended_path->zones();
  ASSERT_EQ(zones.size(), 3u);
  for (const CornerBlendZone& z : zones)
  {
    const double t0 = blended->profile().timeAt(z.start_time), t1 = blended->profile().timeAt(z.end_time);
    ASSERT_LT(t0, t1);
    double slowest = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= 200; ++k)
    {
      const Kinematics s = kinematicsAt(*blended, t0 + (t1 - t0) * k / 200.0);
      slowest = std::min(slowest, std::max(s.velocity.linear.norm(), s.velocity.angular.norm()));
      EXPECT_LE(s.velocity.linear.norm(), 1.0 + 1e-9);
      EXPECT_LE(s.velocity.angular.norm(), 1.0 + 1e-9);
      EXPECT_LE(s.acceleration.linear.norm(), 2.0 + 1e-9);
      EXPECT_LE(s.acceleration.angular.norm(), 2.0 + 1e-9);
    }
    EXPECT_GT(slowest, 0.05) << "corner " << z.corner;
    const Kinematics at_corner = kinematicsAt(*blended, blended->profile().timeAt(times[z.corner]));
    EXPECT_GT(at_corner.velocity.linear.norm(), 0.05) << "corner " << z.corner;
  }
}

TEST(CornerBlendRequest, TimeOptimalThroughBlendsIsFasterThanStoppingAtEveryCorner)
{
  for (const char* geometry : { "double_geodesic", "screw" })
  {
    TrajectoryRequest r = blendedRequest(0.25);
    r.geometry = geometry;
    r.timing = "time_optimal";
    r.max_linear_velocity = 1.0;
    r.max_angular_velocity = 1.0;
    r.max_linear_acceleration = 1.5;
    r.max_angular_acceleration = 1.5;
    r.sample_count = 400;
    const TrajectoryResult blended = generate(r, test::unhurriedLimits());
    r.blend_radius = 0.0;
    const TrajectoryResult sharp = generate(r, test::unhurriedLimits());
    EXPECT_LT(blended.duration, 0.9 * sharp.duration) << geometry;
    EXPECT_LE(blended.figures.max_linear_speed, 1.0 + 1e-9);
    EXPECT_LE(blended.figures.max_linear_acceleration, 1.5 + 1e-9);
    // At rest only at the two ends: every interior sample of the blended motion moves.
    for (std::size_t i = 1; i + 1 < blended.samples.size(); ++i)
      EXPECT_GT(blended.samples[i].velocity.linear.norm() + blended.samples[i].velocity.angular.norm(), 0.0) << i;
    // At the corners' timed waypoint times the sharp motion is at rest, the blended one is not.
    r.sample_times = sharp.waypoint_times;
    const TrajectoryResult sharp_at_corners = generate(r, test::unhurriedLimits());
    r.blend_radius = 0.25;
    r.sample_times = blended.waypoint_times;
    const TrajectoryResult blended_at_corners = generate(r, test::unhurriedLimits());
    for (std::size_t w = 1; w + 1 < r.waypoints.size(); ++w)
    {
      EXPECT_LT(sharp_at_corners.samples[w].velocity.linear.norm(), 1e-9) << geometry << " " << w;
      EXPECT_GT(blended_at_corners.samples[w].velocity.linear.norm(), 0.05) << geometry << " " << w;
    }
  }
}

// Regression: `piecewise_geodesic` with `blend_radius: 0.3`, `times: [0, 0.001, 100]` (a corner
// blend whose clock runs 10⁵ times faster at one end than at the other) under time_optimal with
// all four bounds reached 466 m/s² against max_linear_acceleration 2, both in its reported
// accelerations and in second differences of 2·10⁵ sampled positions. Now every bound holds on
// 10⁵ samples, by the samples' own rates and by differences of the positions independent of them,
// and so does stretch (whose figures missed the blend's peak).
TEST(CornerBlendRequest, UnevenTimesAroundABlendKeepEveryBound)
{
  for (const char* timing : { "time_optimal", "stretch" })
  {
    SCOPED_TRACE(timing);
    TrajectoryRequest r;
    r.waypoints = { Pose<double>(Quaternion<double>::Identity(), Eigen::Vector3d(0, 0, 0)),
                    Pose<double>(Quaternion<double>::Identity(), Eigen::Vector3d(1, 0, 0)),
                    Pose<double>(Quaternion<double>::Identity(), Eigen::Vector3d(0, 0, 0)) };
    r.curve = "piecewise_geodesic";
    r.blend_radius = 0.3;
    r.times = { 0.0, 0.001, 100.0 };
    r.timing = timing;
    r.max_linear_velocity = 1.0;
    r.max_angular_velocity = 1.0;
    r.max_linear_acceleration = 2.0;
    r.max_angular_acceleration = 2.0;
    r.sample_count = 100000;
    const TrajectoryResult out = generate(r, test::unhurriedLimits());
    double peak_v = 0.0, peak_a = 0.0, differenced_a = 0.0;
    for (std::size_t i = 0; i < out.samples.size(); ++i)
    {
      peak_v = std::max(peak_v, out.samples[i].velocity.linear.norm());
      peak_a = std::max(peak_a, out.samples[i].acceleration.linear.norm());
      if (i > 0 && i + 1 < out.samples.size())
      {
        const double h0 = out.samples[i].time - out.samples[i - 1].time;
        const double h1 = out.samples[i + 1].time - out.samples[i].time;
        const Eigen::Vector3d d2 = 2.0 * ((out.samples[i + 1].pose.p - out.samples[i].pose.p) / h1 -
                                          (out.samples[i].pose.p - out.samples[i - 1].pose.p) / h0) /
                                   (h0 + h1);
        differenced_a = std::max(differenced_a, d2.norm());
      }
    }
    EXPECT_LE(peak_v, 1.0 * (1.0 + 1e-6));
    EXPECT_LE(peak_a, 2.0 * (1.0 + 1e-6));
    // Second differences of a motion whose acceleration jumps (time_optimal) smear each jump over
    // a sample step: they stay within the bound up to that smearing's rounding.
    EXPECT_LE(differenced_a, 2.0 * (1.0 + 1e-3));
    EXPECT_LE(out.figures.max_linear_acceleration, 2.0 * (1.0 + 1e-6));
    EXPECT_GE(out.figures.max_linear_acceleration, peak_a * (1.0 - 1e-6));
  }
}
