// The sphere S^m, m ≥ 2 (Crouch, Kun, Silva Leite, §4): geodesics (eqs. 17/18), de
// Casteljau of any degree, Hermite Case 1 and start-data Case 2, the energy of eq. 32, the
// S³ = unit quaternions comparison with SO(3) (§4.1), and the sphere planner of the CLI.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <unsupported/Eigen/MatrixFunctions>

#include "se3_interpolation/curves/blended_spline.h"
#include "se3_interpolation/curves/hermite.h"
#include "se3_interpolation/curves/interpolating_spline.h"
#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/planner/planner.h"
#include "test_utils.h"

using namespace se3_interpolation;
using Eigen::VectorXd;

namespace
{
constexpr double kPi = 3.14159265358979323846;

/// A random point at angle `angle` from x.
VectorXd pointAtAngle(std::mt19937& rng, const VectorXd& x, double angle)
{
  VectorXd d = test::randomUnitVectorX(rng, static_cast<int>(x.size()));
  d = (d - d.dot(x) * x).normalized();
  return std::cos(angle) * x + std::sin(angle) * d;
}

VectorXd randomTangent(std::mt19937& rng, const VectorXd& x, double length)
{
  VectorXd d = test::randomUnitVectorX(rng, static_cast<int>(x.size()));
  return length * (d - d.dot(x) * x).normalized();
}

/// S_{a,b}: the unit generator in so(m+1) rotating a towards b in span(a, b) (eq. 18, from the
/// Gram–Schmidt frame x̂_1 = a, x̂_2 ∈ span(a, b)); S a = x̂_2, S x̂_2 = −a.
Eigen::MatrixXd planeGenerator(const VectorXd& a, const VectorXd& b)
{
  const VectorXd e2 = (b - b.dot(a) * a).normalized();
  return e2 * a.transpose() - a * e2.transpose();
}

/// Ambient position, velocity and second derivative from a jet.
void ambient(const VectorX<Jet<2>>& x, VectorXd* p, VectorXd* v, VectorXd* a)
{
  p->resize(x.size());
  v->resize(x.size());
  a->resize(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i)
  {
    (*p)[i] = x[i].value();
    (*v)[i] = x[i].derivative(1);
    (*a)[i] = x[i].derivative(2);
  }
}

/// Eq. 32 on the test side: composite Simpson of ⟨ẍ, ẍ⟩ − ⟨x, ẍ⟩² over [t0, t1].
double energySimpson(const Curve<Sphere>& c, double t0, double t1, int intervals = 2000)
{
  const double h = (t1 - t0) / intervals;
  double s = 0.0;
  for (int k = 0; k <= intervals; ++k)
  {
    VectorXd p, v, a;
    const Side side = k == intervals ? Side::kLeft : Side::kRight;
    ambient(c.jet(Jet<2>::variable(t0 + k * h), side), &p, &v, &a);
    const double f = a.squaredNorm() - std::pow(p.dot(a), 2);
    s += f * (k == 0 || k == intervals ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0));
  }
  return s * h / 3.0;
}

VectorXd quaternionVector(const Quaternion<double>& q)
{
  VectorXd v(4);
  v << q.w(), q.x(), q.y(), q.z();
  return v;
}
Quaternion<double> rotationOf(const Eigen::Matrix3d& r)
{
  return Quaternion<double>(Eigen::Quaterniond(r));
}
}  // namespace

// ---- Geodesics ---------------------------------------------------------------------------

TEST(SphereGeodesic, EqualsTheGreatCircleFormulasSeventeenAndEighteen)
{
  std::mt19937 rng(1);
  for (int dim : { 3, 4, 7 })
    for (int trial = 0; trial < 50; ++trial)
    {
      const VectorXd a = test::randomUnitVectorX(rng, dim);
      const double theta = std::uniform_real_distribution<double>(0.05, kPi - 0.05)(rng);
      const VectorXd b = pointAtAngle(rng, a, theta);
      const double th = std::acos(a.dot(b));
      const Eigen::MatrixXd s = planeGenerator(a, b);
      for (double lambda : { -0.3, 0.0, 0.25, 0.5, 0.9, 1.0, 1.4 })
      {
        const VectorXd g = geodesic<Sphere>(a, b, lambda);
        const VectorXd eq17 = (std::sin((1 - lambda) * th) * a + std::sin(lambda * th) * b) / std::sin(th);
        const VectorXd eq18 = (lambda * th * s).exp() * a;
        EXPECT_LT((g - eq17).norm(), 1e-13);
        EXPECT_LT((g - eq18).norm(), 1e-13);
        EXPECT_NEAR(g.norm(), 1.0, 1e-15);
      }
    }
}

TEST(SphereGeodesic, AccurateNearZeroAndNearAntipodalAndRejectsAntipodal)
{
  std::mt19937 rng(2);
  const VectorXd a = test::randomUnitVectorX(rng, 5);
  for (double theta : { 1e-12, 1e-7, kPi - 1e-6, kPi - 1e-9 })
  {
    const VectorXd b = pointAtAngle(rng, a, theta);
    const VectorXd v = Sphere::log<double>(a, b);
    EXPECT_NEAR(v.norm(), theta, 1e-12 * theta + 1e-15 * kPi);
    // The normal component is the rounding of b − ⟨a, b⟩ a amplified by θ/sin θ (large near −a).
    EXPECT_NEAR(v.dot(a), 0.0, 4 * std::numeric_limits<double>::epsilon() * theta / std::sin(theta));
    EXPECT_LT((Sphere::exp<double>(a, v) - b).norm(), 1e-14);
  }
  EXPECT_THROW(Sphere::log<double>(a, VectorXd(-a)), NonUniqueGeodesicError);
}

// ---- De Casteljau of any degree --------------------------------------------------------------

TEST(SphereDeCasteljau, AnyDegreeStaysOnTheSphereWithTheBoundaryVelocitiesOfTheorem42)
{
  // dp/dλ(0) = n log(x_0, x_1) and dp/dλ(1) = −n log(x_n, x_{n−1}) (Thm 4.2 for n = 3, Thm 2.5).
  std::mt19937 rng(3);
  for (int dim : { 3, 4, 6 })
    for (int degree = 1; degree <= 6; ++degree)
    {
      std::vector<VectorXd> x{ test::randomUnitVectorX(rng, dim) };
      for (int i = 0; i < degree; ++i)
        x.push_back(pointAtAngle(rng, x.back(), std::uniform_real_distribution<double>(0.2, 1.2)(rng)));
      const BezierCurve<Sphere> c(x, 0.0, 1.0);
      for (double lambda = 0.0; lambda <= 1.0; lambda += 0.05)
        EXPECT_NEAR(c.value(lambda).norm(), 1.0, 1e-14);
      VectorXd p, v, a;
      ambient(c.jet(Jet<2>::variable(0.0), Side::kRight), &p, &v, &a);
      EXPECT_LT((p - x.front()).norm(), 1e-14);
      EXPECT_LT((v - degree * Sphere::log<double>(x[0], x[1])).norm(), 1e-12);
      ambient(c.jet(Jet<2>::variable(1.0), Side::kLeft), &p, &v, &a);
      EXPECT_LT((p - x.back()).norm(), 1e-13);
      EXPECT_LT((v + degree * Sphere::log<double>(x[degree], x[degree - 1])).norm(), 1e-11);
    }
}

TEST(SphereDeCasteljau, CubicEqualsTheNestedGreatCircleFormula)
{
  // Eqs. 19–21: the cubic written with f(t, θ) = sin(tθ)/sin θ, g(t, θ) = sin((1 − t)θ)/sin θ
  // and the angles θ_i^k(t) between consecutive points of each level (the printed eq. 21 keeps
  // only the index 0 of θ_i^k; each level-k point uses its own angle).
  std::mt19937 rng(4);
  auto f = [](double t, double th) { return std::sin(t * th) / std::sin(th); };
  auto g = [](double t, double th) { return std::sin((1 - t) * th) / std::sin(th); };
  auto beta1 = [&](double t, const VectorXd& a, const VectorXd& b) {
    const double th = std::acos(std::min(1.0, a.dot(b)));
    return VectorXd(g(t, th) * a + f(t, th) * b);
  };
  for (int dim : { 3, 5 })
    for (int trial = 0; trial < 20; ++trial)
    {
      std::vector<VectorXd> x{ test::randomUnitVectorX(rng, dim) };
      for (int i = 0; i < 3; ++i)
        x.push_back(pointAtAngle(rng, x.back(), std::uniform_real_distribution<double>(0.3, 1.3)(rng)));
      const BezierCurve<Sphere> c(x, 0.0, 1.0);
      for (double t : { 0.1, 0.33, 0.5, 0.71, 0.95 })
      {
        const VectorXd b01 = beta1(t, x[0], x[1]), b12 = beta1(t, x[1], x[2]), b23 = beta1(t, x[2], x[3]);
        const VectorXd b012 = beta1(t, b01, b12), b123 = beta1(t, b12, b23);
        EXPECT_LT((c.value(t) - beta1(t, b012, b123)).norm(), 1e-13);
      }
    }
}

// ---- Case 1 (Hermite) and Case 2 (start data) ----------------------------------------------

TEST(SphereHermite, CaseOneBoundaryValuesAndCrouchsControlPoints)
{
  // Case 1 (S^m): p(t_0) = x_0, p(t_1) = x_3, ṗ(t_0) = V̂_0, ṗ(t_1) = V̂_1; control points
  // x_1 = exp(V_0^1) x_0, x_2 = exp(−V_2^1) x_3 with V_0^1 = θ_0 S_{x_0, V̂_0}, θ_0 = h|V̂_0|/3
  // (eqs. 24–26), computed here with the matrix exponential of so(m+1).
  std::mt19937 rng(5);
  for (int dim : { 3, 4, 6 })
    for (int trial = 0; trial < 10; ++trial)
    {
      const VectorXd x0 = test::randomUnitVectorX(rng, dim);
      const VectorXd x3 = pointAtAngle(rng, x0, 1.0);
      const VectorXd v0 = randomTangent(rng, x0, 1.5), v1 = randomTangent(rng, x3, 0.7);
      const double t0 = 0.5, t1 = 2.0, h = t1 - t0;
      const HermiteSpline<Sphere> c({ x0, x3 }, { t0, t1 }, { v0, v1 });
      VectorXd p, v, a;
      ambient(c.jet(Jet<2>::variable(t0), Side::kRight), &p, &v, &a);
      EXPECT_LT((p - x0).norm(), 1e-15);
      EXPECT_LT((v - v0).norm(), 1e-13);
      ambient(c.jet(Jet<2>::variable(t1), Side::kLeft), &p, &v, &a);
      EXPECT_LT((p - x3).norm(), 1e-14);
      EXPECT_LT((v - v1).norm(), 1e-13);
      const auto control = c.controlPoints();
      ASSERT_EQ(control.size(), 4U);
      const VectorXd x1 = (h * v0.norm() / 3.0 * planeGenerator(x0, v0)).exp() * x0;
      const VectorXd x2 = (-h * v1.norm() / 3.0 * planeGenerator(x3, v1)).exp() * x3;
      EXPECT_LT((control[1] - x1).norm(), 1e-13);
      EXPECT_LT((control[2] - x2).norm(), 1e-13);
      for (double t = t0; t <= t1; t += 0.01)
        EXPECT_NEAR(c.value(t).norm(), 1.0, 1e-14);
    }
}

TEST(SphereHermite, CaseTwoStartDataGiveVelocityAndCovariantAccelerationAndC2)
{
  // Case 2 (S^m) / end_condition start: ṗ(t_0) = V̂_0 and D²p/dt²(0) = p̈ − ⟨p, p̈⟩ p = Ŵ_0 (eq. 28),
  // computed here from the ambient jets; forward through several waypoints the curve is C² in
  // R^{m+1} (ambient velocity and second derivative agree at every waypoint).
  std::mt19937 rng(6);
  for (int dim : { 3, 5 })
    for (int trial = 0; trial < 5; ++trial)
    {
      std::vector<VectorXd> x{ test::randomUnitVectorX(rng, dim) };
      for (int i = 0; i < 3; ++i)
        x.push_back(pointAtAngle(rng, x.back(), 0.4));
      const std::vector<double> t{ 0.0, 1.0, 2.0, 3.0 };
      const VectorXd v0 = 0.4 * Sphere::log<double>(x[0], x[1]).normalized();
      const VectorXd w0 = randomTangent(rng, x[0], 0.1);
      const auto c = makeInterpolatingSpline<Sphere>(x, t, EndCondition::kStart, v0, VectorXd(v0 * 0.0), w0);
      VectorXd p, v, a;
      ambient(c->jet(Jet<2>::variable(0.0), Side::kRight), &p, &v, &a);
      EXPECT_LT((v - v0).norm(), 1e-12);
      EXPECT_LT((a - p.dot(a) * p - w0).norm(), 1e-9);
      for (std::size_t i = 0; i < x.size(); ++i)
        EXPECT_LT((c->value(t[i]) - x[i]).norm(), 1e-11);
      for (std::size_t i = 1; i + 1 < x.size(); ++i)
      {
        VectorXd pl, vl, al, pr, vr, ar;
        ambient(c->jet(Jet<2>::variable(t[i]), Side::kLeft), &pl, &vl, &al);
        ambient(c->jet(Jet<2>::variable(t[i]), Side::kRight), &pr, &vr, &ar);
        EXPECT_LT((vl - vr).norm(), 1e-9 * (1 + vl.norm()));
        EXPECT_LT((al - ar).norm(), 1e-8 * (1 + al.norm()));
      }
      for (double s = 0.0; s <= 3.0; s += 0.05)
        EXPECT_NEAR(c->value(s).norm(), 1.0, 1e-14);
    }
}

// ---- Energy (eq. 32) -----------------------------------------------------------------------

TEST(SphereEnergy, GreatAndSmallCirclesAndTheQuadratureOfEquation32)
{
  // A great circle at constant speed has zero covariant acceleration; a circle of angular
  // radius ρ traversed at angular rate ω has |D²x/dt²| = ω² sin ρ cos ρ (x = (sin ρ cos ωt,
  // sin ρ sin ωt, cos ρ): ẍ = −ω² sin ρ (cos ωt, sin ωt, 0), ⟨x, ẍ⟩ = −ω² sin² ρ), so eq. 32
  // gives T ω⁴ sin²ρ cos²ρ. The blended spline through points of such a circle at times
  // proportional to their angles is that circle (Pobegailo's construction reproduces circles).
  const double rho = 1.0, omega = 1.3;
  const std::vector<double> phi{ 0.0, 0.7, 1.5, 2.0, 2.9 };
  std::vector<VectorXd> small, great;
  std::vector<double> t;
  for (double a : phi)
  {
    small.push_back(Eigen::Vector3d(std::sin(rho) * std::cos(a), std::sin(rho) * std::sin(a), std::cos(rho)));
    great.push_back(Eigen::Vector3d(std::cos(a), std::sin(a), 0.0));
    t.push_back(a / omega);
  }
  const BlendedSpline<Sphere> cs(small, t, 2), cg(great, t, 2);
  const double duration = t.back() - t.front();
  for (double s = t.front(); s <= t.back(); s += 0.05)
  {
    const VectorXd expected(Eigen::Vector3d(std::sin(rho) * std::cos(omega * s), std::sin(rho) * std::sin(omega * s),
                                            std::cos(rho)));
    EXPECT_LT((cs.value(s) - expected).norm(), 1e-13);
  }
  const CurveFigures fs = measureCurve(cs, 1.0), fg = measureCurve(cg, 1.0);
  const double e = duration * std::pow(omega, 4) * std::pow(std::sin(rho) * std::cos(rho), 2);
  EXPECT_NEAR(fs.energy, e, 1e-12 * e);
  // The sphere's motion is the angular channel; the linear one stays 0.
  EXPECT_EQ(fs.length, 0.0);
  EXPECT_EQ(fs.max_linear_speed, 0.0);
  EXPECT_EQ(fs.max_linear_acceleration, 0.0);
  EXPECT_NEAR(fs.rotation_length, duration * omega * std::sin(rho), 1e-12);
  EXPECT_NEAR(fs.max_angular_speed, omega * std::sin(rho), 1e-12);
  EXPECT_NEAR(fs.max_angular_acceleration, omega * omega * std::sin(rho) * std::cos(rho), 1e-12);
  EXPECT_LT(fg.energy, 1e-25);
  EXPECT_NEAR(fg.rotation_length, omega * duration, 1e-12);

  // A Hermite cubic: the library's energy against Simpson's rule on eq. 32 as printed.
  std::mt19937 rng(7);
  const VectorXd x0 = test::randomUnitVectorX(rng, 4);
  const VectorXd x3 = pointAtAngle(rng, x0, 1.2);
  const HermiteSpline<Sphere> h({ x0, x3 }, { 0.0, 1.5 }, { randomTangent(rng, x0, 2.0), randomTangent(rng, x3, 1.0) });
  const double simpson = energySimpson(h, 0.0, 1.5);
  EXPECT_NEAR(measureCurve(h, 1.0).energy, simpson, 1e-9 * simpson);
}

// ---- S³ = unit quaternions versus SO(3) (§4.1) -----------------------------------------------

TEST(SphereS3, CubicOnS3EqualsTheSo3CubicOfTheCorrespondingRotations)
{
  // §4.1's example: g_0 … g_3 in SO(3) and the unit quaternions q_0 … q_3 (signs chosen with
  // positive consecutive dot products, so every S³ geodesic is the short one). The great circles
  // of S³ through q are q Exp(s ω / 2) = the SO(3) geodesics: the two de Casteljau cubics agree.
  const double r2 = std::sqrt(2.0) / 2.0, r3 = std::sqrt(3.0) / 2.0;
  Eigen::Matrix3d g1, g2, g3;
  g1 << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  g2 << r2, -r2, 0, 0, 0, -1, r2, r2, 0;
  g3 << 0, -1, 0, 0.5, 0, -r3, r3, 0, 0.5;
  std::vector<Quaternion<double>> q{ Quaternion<double>::Identity(), rotationOf(g1), rotationOf(g2), rotationOf(g3) };
  for (std::size_t i = 1; i < q.size(); ++i)
    if (q[i].coeffs().dot(q[i - 1].coeffs()) < 0.0)
      q[i].coeffs() *= -1.0;
  std::vector<VectorXd> s;
  for (const auto& qi : q)
    s.push_back(quaternionVector(qi));
  const BezierCurve<So3> on_so3(q, 0.0, 1.0);
  const BezierCurve<Sphere> on_s3(s, 0.0, 1.0);
  double worst = 0.0;
  for (double t = 0.0; t <= 1.0; t += 0.01)
  {
    const VectorXd a = quaternionVector(on_so3.value(t)), b = on_s3.value(t);
    worst = std::max(worst, std::min((a - b).norm(), (a + b).norm()));
  }
  std::cout << "[ S3 vs SO(3) ] §4.1 example cubic: largest quaternion difference " << worst << "\n";
  EXPECT_LT(worst, 1e-14);

  // The double cover matters: −q_2 is the same rotation, but the S³ curve then takes the long
  // way (a different motion), while the SO(3) curve is unchanged.
  std::vector<VectorXd> flipped = s;
  flipped[2] = -flipped[2];
  std::vector<Quaternion<double>> qf = q;
  qf[2].coeffs() *= -1.0;
  const BezierCurve<Sphere> on_s3_flipped(flipped, 0.0, 1.0);
  const BezierCurve<So3> on_so3_flipped(qf, 0.0, 1.0);
  double moved = 0.0, same = 0.0;
  for (double t = 0.05; t < 1.0; t += 0.05)
  {
    const VectorXd a = on_s3_flipped.value(t), b = on_s3.value(t);
    moved = std::max(moved, std::min((a - b).norm(), (a + b).norm()));
    same = std::max(same, rotationAngle(Quaternion<double>(on_so3_flipped.value(t).conjugate() * on_so3.value(t))));
  }
  EXPECT_GT(moved, 0.1);
  EXPECT_LT(same, 1e-14);
}

TEST(SphereS3, HermiteCubicOnS3IsTheSo3HermiteAndTheEnergyIsAQuarter)
{
  // Velocities: q̇ = ½ q (0, ω_b) for the body angular velocity ω_b (|q̇| = |ω|/2); then the S³
  // Hermite cubic is the SO(3) one, and |D²q/dt²| = |ω̇|/2, so the energy of eq. 32 on S³ is a
  // quarter of ∫ |ω̇|² dt on SO(3).
  std::mt19937 rng(8);
  double worst = 0.0;
  for (int trial = 0; trial < 10; ++trial)
  {
    const auto poses = test::randomPolygon(rng, 4, 0.8);
    const std::vector<double> t{ 0.0, 0.7, 1.9, 2.5 };
    std::vector<Quaternion<double>> q;
    std::vector<Eigen::Vector3d> w;
    std::vector<VectorXd> s, sv;
    for (const auto& p : poses)
    {
      q.push_back(p.q);
      if (q.size() > 1 && q.back().coeffs().dot(q[q.size() - 2].coeffs()) < 0.0)
        q.back().coeffs() *= -1.0;
      w.push_back(test::randomUnitVector<3>(rng) * 0.8);
      s.push_back(quaternionVector(q.back()));
      sv.push_back(quaternionVector(Quaternion<double>(q.back() * Quaternion<double>(0.0, w.back().x() / 2,
                                                                                       w.back().y() / 2,
                                                                                       w.back().z() / 2))));
    }
    const HermiteSpline<So3> on_so3(q, t, w);
    const HermiteSpline<Sphere> on_s3(s, t, sv);
    // Simpson on ∫ |ω̇|² per segment (ω̇ jumps at the waypoints: the cubics are C¹), with ω̇ from
    // the quaternion jet (kinematics.h, zero translation).
    double so3_energy = 0.0;
    for (std::size_t i = 0; i + 1 < t.size(); ++i)
    {
      const int n = 1000;
      const double h = (t[i + 1] - t[i]) / n;
      double sum = 0.0;
      for (int k = 0; k <= n; ++k)
      {
        const double tk = t[i] + k * h;
        const VectorXd a = quaternionVector(on_so3.value(tk)), b = on_s3.value(tk);
        worst = std::max(worst, std::min((a - b).norm(), (a + b).norm()));
        const Quaternion<Jet<2>> qj = on_so3.jet(Jet<2>::variable(tk), k == n ? Side::kLeft : Side::kRight);
        const Kinematics kin = kinematicsFromJet(Pose<Jet<2>>(qj, Vector3<Jet<2>>::Zero()));
        sum += kin.acceleration.angular.squaredNorm() * (k == 0 || k == n ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0));
      }
      so3_energy += sum * h / 3.0;
    }
    const double s3_energy = measureCurve(on_s3, 1.0).energy;
    EXPECT_NEAR(s3_energy, so3_energy / 4.0, 1e-9 * so3_energy);
  }
  std::cout << "[ S3 vs SO(3) ] Hermite cubics: largest quaternion difference " << worst << "\n";
  EXPECT_LT(worst, 1e-13);
}

// ---- The sphere planner (--space sphere) -----------------------------------------------------

namespace
{
SphereRequest circleRequest(const std::string& curve)
{
  SphereRequest r;
  for (double a : { 0.0, 0.6, 1.3, 1.9, 2.6 })
    r.waypoints.push_back(Eigen::Vector4d(std::cos(a) * 0.8, std::sin(a) * 0.8, 0.6 * std::cos(a), 0.6 * std::sin(a)));
  r.curve = curve;
  r.sample_count = 41;
  return r;
}

std::string errorOf(const SphereRequest& r)
{
  try
  {
    generate(r, test::unhurriedLimits());
  }
  catch (const InterpolationError& e)
  {
    return e.what();
  }
  return "no error";
}
}  // namespace

TEST(SpherePlanner, EveryCurveOnS3)
{
  for (const char* curve : { "piecewise_geodesic", "bezier", "bspline", "interpolating", "hermite", "blended" })
  {
    SphereRequest r = circleRequest(curve);
    r.waypoints[2] = Eigen::Vector4d(0.3, 0.9, 0.1, -0.3).normalized();
    const SphereResult out = generate(r, test::unhurriedLimits());
    ASSERT_EQ(out.samples.size(), 41U) << curve;
    for (const auto& s : out.samples)
    {
      EXPECT_NEAR(s.point.norm(), 1.0, 1e-14) << curve;
      EXPECT_NEAR(s.velocity.dot(s.point), 0.0, 1e-12) << curve;
      EXPECT_NEAR(s.acceleration.dot(s.point), 0.0, 1e-12) << curve;
    }
    EXPECT_LT((out.samples.front().point - r.waypoints.front()).norm(), 1e-14) << curve;
    EXPECT_LT((out.samples.back().point - r.waypoints.back()).norm(), 1e-12) << curve;
    const bool interpolates = std::string(curve) != "bezier" && std::string(curve) != "bspline";
    if (interpolates)
    {
      for (std::size_t i = 0; i < r.waypoints.size(); ++i)
        EXPECT_LT((out.point_at(out.waypoint_times[i]) - r.waypoints[i].normalized()).norm(), 1e-11) << curve << i;
    }
    EXPECT_GT(out.figures.rotation_length, 0.0);
    EXPECT_TRUE(std::isfinite(out.figures.energy));
  }
}

TEST(SpherePlanner, ChordTimingStartConditionAndBounds)
{
  // Chord spacing: the times are proportional to the great-circle angles (here 0.6, 0.7, 0.6, 0.7
  // rad: the waypoints lie on a great circle of S³), over `duration`.
  SphereRequest r = circleRequest("blended");
  r.duration = 5.6;
  const SphereResult a = generate(r, test::unhurriedLimits());
  const std::vector<double> expected{ 0.0, 1.2, 2.6, 3.8, 5.2 };
  for (std::size_t i = 0; i < expected.size(); ++i)
    EXPECT_NEAR(a.waypoint_times[i], expected[i] * 5.6 / 5.2, 1e-12);
  // On a great circle at times proportional to the angles the blended spline is the great
  // circle at constant speed: no covariant acceleration, speed = angle / time.
  EXPECT_NEAR(a.figures.max_angular_speed, 2.6 / 5.6, 1e-12);
  EXPECT_LT(a.figures.max_angular_acceleration, 1e-12);

  // Bounds stretch the time axis until the peaks are within them.
  r.curve = "hermite";
  r.duration = 1.0;
  r.max_angular_velocity = 1.5;
  r.max_angular_acceleration = 2.0;
  const SphereResult b = generate(r, test::unhurriedLimits());
  EXPECT_GT(b.time_scale, 1.0);
  EXPECT_LE(b.figures.max_angular_speed, 1.5 * (1 + 1e-9));
  EXPECT_LE(b.figures.max_angular_acceleration, 2.0 * (1 + 1e-9));
  EXPECT_NEAR(b.duration, b.time_scale, 1e-12);

  // end_condition start (Crouch Case 2): the first sample has the requested velocity and
  // covariant acceleration.
  r = circleRequest("interpolating");
  r.times = { 0.0, 1.0, 2.0, 3.0, 4.0 };
  r.end_condition = "start";
  const VectorXd x0 = r.waypoints[0];
  r.start_velocity = Eigen::Vector4d(0.0, 0.48, 0.0, 0.36);  // tangent: x0 = (0.8, 0, 0.6, 0)
  r.start_acceleration = Eigen::Vector4d(0.0, 0.0, 0.0, 0.05);
  const SphereResult c = generate(r, test::unhurriedLimits());
  EXPECT_LT((c.samples.front().velocity - r.start_velocity).norm(), 1e-12);
  EXPECT_LT((c.samples.front().acceleration - r.start_acceleration).norm(), 1e-9);
  for (std::size_t i = 0; i < r.waypoints.size(); ++i)
    EXPECT_LT((c.point_at(r.times[i]) - r.waypoints[i]).norm(), 1e-11);
}

TEST(SpherePlanner, ErrorsNameTheFieldAndIndex)
{
  SphereRequest r = circleRequest("blended");
  r.waypoints[3] = Eigen::Vector4d(0.0, 0.0, 0.5, 0.0);
  EXPECT_NE(errorOf(r).find("waypoints[3]: norm 0.5"), std::string::npos) << errorOf(r);
  r = circleRequest("blended");
  r.waypoints[1][2] = std::nan("");
  EXPECT_NE(errorOf(r).find("waypoints[1][2]: nan is not a finite number"), std::string::npos) << errorOf(r);
  r = circleRequest("blended");
  r.waypoints[2] = Eigen::Vector3d(0, 0, 1);
  EXPECT_NE(errorOf(r).find("waypoints[2]: has 3 components; waypoints[0] has 4"), std::string::npos) << errorOf(r);
  r = circleRequest("blended");
  r.waypoints[2] = -r.waypoints[1];
  EXPECT_NE(errorOf(r).find("waypoints[1] and waypoints[2]"), std::string::npos) << errorOf(r);
  EXPECT_THROW(generate(r, test::unhurriedLimits()), NonUniqueGeodesicError);
  r = circleRequest("blended");
  r.waypoints = { Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1) };
  EXPECT_NE(errorOf(r).find("waypoints[0]: has 2 components"), std::string::npos) << errorOf(r);
  r = circleRequest("blended");
  r.geometry = "screw";
  EXPECT_NE(errorOf(r).find("geometry: not used on the sphere"), std::string::npos) << errorOf(r);
  r = circleRequest("blended");
  r.max_linear_velocity = 1.0;
  EXPECT_NE(errorOf(r).find("max_linear_velocity: not used on the sphere"), std::string::npos) << errorOf(r);
  r = circleRequest("interpolating");
  r.end_condition = "start";
  r.start_velocity = Eigen::Vector4d(1.0, 0.0, 0.0, 0.0);  // along x0 = (0.8, 0, 0.6, 0): not tangent
  EXPECT_NE(errorOf(r).find("start_velocity: is not tangent"), std::string::npos) << errorOf(r);
  r.start_velocity = Eigen::Vector3d(0.0, 1.0, 0.0);
  EXPECT_NE(errorOf(r).find("start_velocity: has 3 components; expected 4"), std::string::npos) << errorOf(r);
  r = circleRequest("hermite");
  r.velocities.assign(3, Eigen::Vector4d::Zero());
  EXPECT_NE(errorOf(r).find("velocities: 3 given for 5 waypoints"), std::string::npos) << errorOf(r);
  r = circleRequest("blended");
  r.continuity = 9;
  EXPECT_NE(errorOf(r).find("continuity: 9"), std::string::npos) << errorOf(r);
  r = circleRequest("catmull_rom");
  EXPECT_NE(errorOf(r).find("curve: unknown value 'catmull_rom'"), std::string::npos) << errorOf(r);
  r = circleRequest("blended");
  r.waypoints[2] = r.waypoints[1];
  EXPECT_NE(errorOf(r).find("waypoints[1] and waypoints[2]: identical"), std::string::npos) << errorOf(r);
  r.times = { 0.0, 1.0, 2.0, 3.0, 4.0 };  // with explicit times the body dwells
  EXPECT_EQ(errorOf(r), "no error");
}

// sphereKinematicsFromJet takes the kinematics of x/|x|: a jet that leaves the sphere radially
// (by rounding, near the conjugate point) has the kinematics of its projection. Here
// x(s) = (1 + e s + d s^2) gamma(s) with gamma the great circle cos(th) e1 + sin(th) e2,
// th = w s + b s^2/2: velocity w e2 and covariant acceleration b e2 (the tangential part; the
// normal part -w^2 e1 is removed), whatever e and d.
TEST(SphereKinematics, JetOffTheSphereHasTheKinematicsOfItsProjection)
{
  const double w = 0.7, b = -1.3;
  for (const double e : { 0.0, 1e-3, 0.25 })
  {
    const double d = 3.0 * e;
    const Jet<2> s = Jet<2>::variable(0.0);
    const Jet<2> radius = 1.0 + e * s + d * s * s;
    const Jet<2> th = w * s + 0.5 * b * s * s;
    VectorX<Jet<2>> x(3);
    x << radius * cos(th), radius * sin(th), Jet<2>(0.0);
    const SphereKinematics k = sphereKinematicsFromJet(x);
    EXPECT_LT((k.point - Eigen::Vector3d(1, 0, 0)).norm(), 1e-15) << e;
    EXPECT_LT((k.velocity - Eigen::Vector3d(0, w, 0)).norm(), 1e-15) << e << ": " << k.velocity.transpose();
    EXPECT_LT((k.acceleration - Eigen::Vector3d(0, b, 0)).norm(), 1e-15) << e << ": " << k.acceleration.transpose();
  }
}
