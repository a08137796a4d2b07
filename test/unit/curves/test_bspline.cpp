// Geodesic B-splines (generalised de Boor, thesis Alg. 4.3.3) on SE(3), SO(3), S^m and R^n:
// agreement with de Casteljau and with Crouch's product form, the classical B-spline in the
// abelian cases (an independent Cox–de Boor recursion), invariances, local support, knot
// validation, knot insertion (the Menelaus question, measured), analytic derivatives,
// boundary derivatives (thesis Prop. 4.2.8/4.2.9, Crouch et al. Thm 2.5/2.9) and figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/curves/bezier.h"
#include "test_utils.h"

using namespace se3_interpolation;
using test::poseDistance;
using test::randomPolygon;
using test::randomPose;
using test::randomUnitVector;
using test::randomKnots;
using test::bezierKnots;

namespace
{
// ---------------------------------------------------------------------------------------
// Independent references (no library B-spline code)
// ---------------------------------------------------------------------------------------

/// Cox–de Boor recursion for the B-spline basis function N_{i,m}(t). Side::kRight uses the
/// half-open intervals [u_i, u_{i+1}), Side::kLeft (u_i, u_{i+1}] (the limit from the left).
double basis(const std::vector<double>& u, std::size_t i, int m, double t, Side side)
{
  if (m == 0)
  {
    if (side == Side::kRight)
      return u[i] <= t && t < u[i + 1] ? 1.0 : 0.0;
    return u[i] < t && t <= u[i + 1] ? 1.0 : 0.0;
  }
  const std::size_t mm = static_cast<std::size_t>(m);
  double r = 0.0;
  if (u[i + mm] > u[i])
    r += (t - u[i]) / (u[i + mm] - u[i]) * basis(u, i, m - 1, t, side);
  if (u[i + mm + 1] > u[i + 1])
    r += (u[i + mm + 1] - t) / (u[i + mm + 1] - u[i + 1]) * basis(u, i + 1, m - 1, t, side);
  return r;
}

/// The classical B-spline Σ N_{i,m}(t) x_i on [u_m, u_N]; the right end is the limit from the left.
template <class V>
V classicalSpline(const std::vector<V>& x, const std::vector<double>& u, int m, double t)
{
  const Side side = t < u[x.size()] ? Side::kRight : Side::kLeft;
  V r = x[0] * 0.0;
  for (std::size_t i = 0; i < x.size(); ++i)
    r += basis(u, i, m, t, side) * x[i];
  return r;
}
double classicalSpline(const std::vector<double>& x, const std::vector<double>& u, int m, double t)
{
  const Side side = t < u[x.size()] ? Side::kRight : Side::kLeft;
  double r = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i)
    r += basis(u, i, m, t, side) * x[i];
  return r;
}

/// Distinct knot values strictly inside the domain (u_m, u_N).
std::vector<double> interiorKnots(const std::vector<double>& u, std::size_t n, int m)
{
  std::vector<double> r;
  for (std::size_t i = static_cast<std::size_t>(m) + 1; i < n; ++i)
    if (u[i] > u[static_cast<std::size_t>(m)] && u[i] < u[n] && (r.empty() || u[i] > r.back()))
      r.push_back(u[i]);
  return r;
}

std::vector<double> linspace(double a, double b, int count)
{
  std::vector<double> r;
  for (int i = 0; i + 1 < count; ++i)
    r.push_back(a + (b - a) * i / (count - 1));
  r.push_back(b);  // exactly, not a rounded a + (b − a)
  return r;
}

// ---------------------------------------------------------------------------------------
// Per-geometry random points and distances
// ---------------------------------------------------------------------------------------
template <class G>
struct Space;

template <>
struct Space<ScrewSe3>
{
  using P = Pose<double>;
  static std::vector<P> polygon(std::mt19937& rng, std::size_t n) { return randomPolygon(rng, n, 1.0); }
  static double distance(const P& a, const P& b) { return poseDistance(a, b); }
};
template <>
struct Space<DoubleGeodesicSe3> : Space<ScrewSe3>
{
};
template <>
struct Space<So3>
{
  using P = Quaternion<double>;
  static std::vector<P> polygon(std::mt19937& rng, std::size_t n)
  {
    std::vector<P> p{ randomPose(rng).q };
    for (std::size_t i = 1; i < n; ++i)
      p.push_back(P(p.back() * randomPose(rng, 1.0).q));
    return p;
  }
  static double distance(const P& a, const P& b) { return rotationAngle(P(a.conjugate() * b)); }
};
template <>
struct Space<Sphere>
{
  using P = Eigen::VectorXd;
  static std::vector<P> polygon(std::mt19937& rng, std::size_t n)
  {
    std::vector<P> p{ test::randomUnitVectorX(rng, 4) };  // S^3
    std::uniform_real_distribution<double> angle(0.1, 1.0);
    for (std::size_t i = 1; i < n; ++i)
    {
      const P& a = p.back();
      P w = test::randomUnitVectorX(rng, 4);
      w = (w - w.dot(a) * a).normalized();
      p.push_back(Sphere::exp(a, P(angle(rng) * w)));
    }
    return p;
  }
  static double distance(const P& a, const P& b) { return (a - b).norm(); }
};
template <>
struct Space<Euclidean>
{
  using P = Eigen::VectorXd;
  static std::vector<P> polygon(std::mt19937& rng, std::size_t n)
  {
    std::normal_distribution<double> d(0.0, 1.0);
    std::vector<P> p;
    for (std::size_t i = 0; i < n; ++i)
      p.push_back(Eigen::Vector3d(d(rng), d(rng), d(rng)));
    return p;
  }
  static double distance(const P& a, const P& b) { return (a - b).norm(); }
};

/// A polygon of n poses whose consecutive relative motions rotate by exactly `angle` (random
/// axis) and translate by `step` m (random direction in the body frame).
std::vector<Pose<double>> fixedStepPolygon(std::mt19937& rng, std::size_t n, double angle, double step)
{
  std::vector<Pose<double>> p{ randomPose(rng) };
  for (std::size_t i = 1; i < n; ++i)
    p.push_back(p.back() *
                Pose<double>(so3Exp<double>(angle * randomUnitVector<3>(rng)), step * randomUnitVector<3>(rng)));
  return p;
}

/// |x − y| / max(1, |x|): relative error with an absolute floor.
double relError(const Eigen::Vector3d& x, const Eigen::Vector3d& y)
{
  return (x - y).norm() / std::max(1.0, x.norm());
}

template <class T>
double median(std::vector<T> v)
{
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

template <class G>
class SE3Test : public ::testing::Test
{
};
using SE3Geometries = ::testing::Types<ScrewSe3, DoubleGeodesicSe3>;
TYPED_TEST_SUITE(SE3Test, SE3Geometries);

template <class G>
class AllGeometries : public ::testing::Test
{
};
using Geometries = ::testing::Types<ScrewSe3, DoubleGeodesicSe3, So3, Sphere, Euclidean>;
TYPED_TEST_SUITE(AllGeometries, Geometries);
}  // namespace

// =======================================================================================
// 1. Bézier knots: de Boor = de Casteljau
// =======================================================================================
TYPED_TEST(AllGeometries, DeBoorOnBezierKnotsIsDeCasteljau)
{
  using Sp = Space<TypeParam>;
  std::mt19937 rng(101);
  for (int trial = 0; trial < 10; ++trial)
    for (std::size_t n = 2; n <= 7; ++n)  // degree 1 … 6 = n − 1
    {
      const int m = static_cast<int>(n) - 1;
      const auto pts = Sp::polygon(rng, n);
      const BSplineCurve<TypeParam> spline(pts, m, bezierKnots(m, -0.5, 2.0));
      const BezierCurve<TypeParam> bezier(pts, -0.5, 2.0);
      for (double t : linspace(-0.5, 2.0, 11))
        EXPECT_LT(Sp::distance(spline.value(t), bezier.value(t)), 1e-13) << "degree " << m << " t " << t;
    }
}

// =======================================================================================
// 2. Abelian cases: the classical B-spline (own Cox–de Boor recursion)
// =======================================================================================
TEST(Classical, BasisIsAPartitionOfUnity)
{
  // Sanity check of the reference itself: Σ_i N_{i,m} = 1 on the domain.
  std::mt19937 rng(201);
  for (int m = 1; m <= 5; ++m)
    for (bool clamped : { true, false })
    {
      const std::size_t n = static_cast<std::size_t>(m) + 4;
      const auto u = randomKnots(rng, n, m, clamped);
      const std::vector<double> ones(n, 1.0);
      for (double t : linspace(u[static_cast<std::size_t>(m)], u[n], 37))
        EXPECT_NEAR(classicalSpline(ones, u, m, t), 1.0, 1e-14);
    }
}

TEST(Classical, EuclideanBSplineIsTheClassicalOne)
{
  std::mt19937 rng(202);
  for (int m = 1; m <= 6; ++m)
    for (bool clamped : { true, false })
      for (int trial = 0; trial < 5; ++trial)
      {
        const std::size_t n = static_cast<std::size_t>(m) + 1 + static_cast<std::size_t>(trial);
        const auto pts = Space<Euclidean>::polygon(rng, n);
        const auto u = randomKnots(rng, n, m, clamped);
        const BSplineCurve<Euclidean> c(pts, m, u);
        for (double t : linspace(u[static_cast<std::size_t>(m)], u[n], 41))
          EXPECT_LT((c.value(t) - classicalSpline(pts, u, m, t)).norm(), 1e-13) << "degree " << m << " t " << t;
      }
}

TYPED_TEST(SE3Test, PureTranslationsGiveTheClassicalBSpline)
{
  std::mt19937 rng(203);
  std::normal_distribution<double> d(0.0, 1.0);
  for (int m = 1; m <= 6; ++m)
    for (bool clamped : { true, false })
      for (int trial = 0; trial < 4; ++trial)
      {
        const std::size_t n = static_cast<std::size_t>(m) + 1 + static_cast<std::size_t>(trial);
        std::vector<Pose<double>> pts;
        std::vector<Eigen::Vector3d> positions;
        for (std::size_t i = 0; i < n; ++i)
        {
          positions.emplace_back(d(rng), d(rng), d(rng));
          pts.emplace_back(Quaternion<double>::Identity(), positions.back());
        }
        const auto u = randomKnots(rng, n, m, clamped);
        const BSplineCurve<TypeParam> c(pts, m, u);
        for (double t : linspace(u[static_cast<std::size_t>(m)], u[n], 41))
        {
          const Pose<double> g = c.value(t);
          EXPECT_LT((g.p - classicalSpline(positions, u, m, t)).norm(), 1e-13) << "degree " << m << " t " << t;
          EXPECT_EQ(rotationAngle(g.q), 0.0);
        }
      }
}

TYPED_TEST(SE3Test, RotationAboutOneAxisFollowsTheClassicalBSplineOfTheAngles)
{
  std::mt19937 rng(204);
  std::uniform_real_distribution<double> step(-2.5, 2.5);
  for (int m = 1; m <= 5; ++m)
    for (int trial = 0; trial < 4; ++trial)
    {
      const std::size_t n = static_cast<std::size_t>(m) + 1 + static_cast<std::size_t>(trial);
      const Eigen::Vector3d axis = randomUnitVector<3>(rng);
      std::vector<double> angles{ step(rng) };
      for (std::size_t i = 1; i < n; ++i)
        angles.push_back(angles.back() + step(rng));  // may wind past ±π: only steps stay < π
      std::vector<Pose<double>> pts;
      for (double a : angles)
        pts.emplace_back(so3Exp<double>(a * axis), Eigen::Vector3d::Zero());
      const auto u = randomKnots(rng, n, m, trial % 2 == 0);
      const BSplineCurve<TypeParam> c(pts, m, u);
      for (double t : linspace(u[static_cast<std::size_t>(m)], u[n], 41))
      {
        const Pose<double> g = c.value(t);
        const Quaternion<double> ref = so3Exp<double>(classicalSpline(angles, u, m, t) * axis);
        EXPECT_LT(rotationAngle(Quaternion<double>(ref.conjugate() * g.q)), 1e-13) << "degree " << m << " t " << t;
        EXPECT_LT(g.p.norm(), 1e-14);
      }
    }
}

TEST(Classical, So3AndSphereAlongOneGreatCircleFollowTheClassicalBSpline)
{
  std::mt19937 rng(205);
  std::uniform_real_distribution<double> step(-2.5, 2.5);
  for (int m = 1; m <= 5; ++m)
  {
    const std::size_t n = static_cast<std::size_t>(m) + 3;
    std::vector<double> angles{ 0.0 };
    for (std::size_t i = 1; i < n; ++i)
      angles.push_back(angles.back() + step(rng));
    const auto u = randomKnots(rng, n, m, false);
    // SO(3): rotations about one axis.
    const Eigen::Vector3d axis = randomUnitVector<3>(rng);
    std::vector<Quaternion<double>> rotations;
    for (double a : angles)
      rotations.push_back(so3Exp<double>(a * axis));
    // S^3: points on the great circle through orthonormal e, f.
    const Eigen::VectorXd e = test::randomUnitVectorX(rng, 4);
    Eigen::VectorXd f = test::randomUnitVectorX(rng, 4);
    f = (f - f.dot(e) * e).normalized();
    std::vector<Eigen::VectorXd> points;
    for (double a : angles)
      points.push_back(std::cos(a) * e + std::sin(a) * f);
    const BSplineCurve<So3> rc(rotations, m, u);
    const BSplineCurve<Sphere> sc(points, m, u);
    for (double t : linspace(u[static_cast<std::size_t>(m)], u[n], 41))
    {
      const double a = classicalSpline(angles, u, m, t);
      EXPECT_LT(rotationAngle(Quaternion<double>(so3Exp<double>(a * axis).conjugate() * rc.value(t))), 1e-13);
      EXPECT_LT((sc.value(t) - (std::cos(a) * e + std::sin(a) * f)).norm(), 1e-13);
    }
  }
}

// =======================================================================================
// 3. Crouch's product form (thesis eq. 4.3–4.5) = de Casteljau = de Boor on Bézier knots
// =======================================================================================
namespace
{
/// The group operations of the bi-invariant geometries, written with the raw exp/log maps.
struct ScrewGroup
{
  using P = Pose<double>;
  using V = Vector6<double>;
  static V log(const P& g) { return se3Log(g); }
  static P exp(const V& v) { return se3Exp(v); }
  static P inverse(const P& g) { return g.inverse(); }
};
struct RotationGroup
{
  using P = Quaternion<double>;
  using V = Eigen::Vector3d;
  static V log(const P& g) { return so3Log(g); }
  static P exp(const V& v) { return so3Exp(v); }
  static P inverse(const P& g) { return g.conjugate(); }
};

/// p_n(t) = g_0 exp(t V_0^1) exp(t V_0^2(t)) ⋯ exp(t V_0^n(t)), g_{k+1} = g_k exp(V_k^1),
/// exp(V_k^j) = exp((1 − t) V_k^{j−1}) exp(t V_{k+1}^{j−1}).
template <class Gr>
typename Gr::P crouchProduct(const std::vector<typename Gr::P>& g, double t)
{
  using P = typename Gr::P;
  using V = typename Gr::V;
  std::vector<V> level;
  for (std::size_t k = 0; k + 1 < g.size(); ++k)
    level.push_back(Gr::log(P(Gr::inverse(g[k]) * g[k + 1])));
  P p = g[0];
  while (!level.empty())
  {
    p = P(p * Gr::exp(V(t * level[0])));
    std::vector<V> next;
    for (std::size_t k = 0; k + 1 < level.size(); ++k)
      next.push_back(Gr::log(P(Gr::exp(V((1.0 - t) * level[k])) * Gr::exp(V(t * level[k + 1])))));
    level = next;
  }
  return p;
}
}  // namespace

TEST(CrouchProductForm, EqualsDeCasteljauAndDeBoorForTheScrewGeometry)
{
  std::mt19937 rng(301);
  for (int trial = 0; trial < 20; ++trial)
    for (std::size_t n = 2; n <= 7; ++n)
    {
      const auto pts = randomPolygon(rng, n, 0.8);
      const int m = static_cast<int>(n) - 1;
      const BezierCurve<ScrewSe3> bezier(pts, 0.0, 1.0);
      const BSplineCurve<ScrewSe3> spline(pts, m, bezierKnots(m, 0.0, 1.0));
      for (double t : { 0.0, 0.13, 0.5, 0.71, 0.98, 1.0 })
      {
        const Pose<double> ref = crouchProduct<ScrewGroup>(pts, t);
        EXPECT_LT(poseDistance(bezier.value(t), ref), 1e-12) << "degree " << m << " t " << t;
        EXPECT_LT(poseDistance(spline.value(t), ref), 1e-12) << "degree " << m << " t " << t;
      }
    }
}

TEST(CrouchProductForm, EqualsDeBoorOnSo3)
{
  std::mt19937 rng(302);
  for (int trial = 0; trial < 20; ++trial)
    for (std::size_t n = 2; n <= 7; ++n)
    {
      const auto pts = Space<So3>::polygon(rng, n);
      const int m = static_cast<int>(n) - 1;
      const BSplineCurve<So3> spline(pts, m, bezierKnots(m, 0.0, 1.0));
      for (double t : { 0.0, 0.27, 0.5, 0.9, 1.0 })
        EXPECT_LT(Space<So3>::distance(spline.value(t), crouchProduct<RotationGroup>(pts, t)), 1e-12);
    }
}

// =======================================================================================
// 4. Invariances and local support
// =======================================================================================
TYPED_TEST(SE3Test, LeftInvariance)
{
  std::mt19937 rng(401);
  for (int m = 1; m <= 5; ++m)
    for (int trial = 0; trial < 5; ++trial)
    {
      const std::size_t n = static_cast<std::size_t>(m) + 3;
      const auto pts = randomPolygon(rng, n);
      const auto u = randomKnots(rng, n, m, trial % 2 == 0);
      const Pose<double> h = randomPose(rng, 3.0, 2.0);
      std::vector<Pose<double>> moved;
      for (const auto& p : pts)
        moved.push_back(h * p);
      const BSplineCurve<TypeParam> a(pts, m, u), b(moved, m, u);
      for (double t : linspace(u[static_cast<std::size_t>(m)], u[n], 17))
        EXPECT_LT(poseDistance(h * a.value(t), b.value(t)), 1e-12);
    }
}

TEST(Invariance, ScrewBSplineIsRightInvariantDoubleGeodesicIsNot)
{
  std::mt19937 rng(402);
  double worst_screw = 0.0;
  double best_double = std::numeric_limits<double>::infinity();
  for (int m = 1; m <= 5; ++m)
    for (int trial = 0; trial < 5; ++trial)
    {
      const std::size_t n = static_cast<std::size_t>(m) + 3;
      const auto pts = randomPolygon(rng, n);
      const auto u = randomKnots(rng, n, m, trial % 2 == 0);
      const Pose<double> h = randomPose(rng, 3.0, 2.0);
      std::vector<Pose<double>> moved;
      for (const auto& p : pts)
        moved.push_back(p * h);
      const BSplineCurve<ScrewSe3> a(pts, m, u), b(moved, m, u);
      const BSplineCurve<DoubleGeodesicSe3> c(pts, m, u), d(moved, m, u);
      // Inside the first span, away from its ends (where every curve passes a control point
      // for clamped knots).
      const std::size_t k = knotSpan(u, n, m, u[static_cast<std::size_t>(m)], Side::kRight);
      const double t_mid = 0.5 * (u[k] + u[k + 1]);
      for (double t : linspace(u[static_cast<std::size_t>(m)], u[n], 17))
        worst_screw = std::max(worst_screw, poseDistance(a.value(t) * h, b.value(t)));
      best_double = std::min(best_double, poseDistance(c.value(t_mid) * h, d.value(t_mid)));
    }
  EXPECT_LT(worst_screw, 1e-11);
  EXPECT_GT(best_double, 1e-3);
}

TEST(Invariance, So3AndSphereAreRotationInvariant)
{
  std::mt19937 rng(403);
  for (int m = 1; m <= 4; ++m)
  {
    const std::size_t n = static_cast<std::size_t>(m) + 3;
    const auto u = randomKnots(rng, n, m, false);
    // SO(3): left and right multiplication (bi-invariant metric).
    const auto rot = Space<So3>::polygon(rng, n);
    const Quaternion<double> h = randomPose(rng, 3.0).q;
    std::vector<Quaternion<double>> left, right;
    for (const auto& q : rot)
    {
      left.emplace_back(h * q);
      right.emplace_back(q * h);
    }
    // S^3: an orthogonal map of R^4.
    const auto pts = Space<Sphere>::polygon(rng, n);
    Eigen::Matrix4d random;
    for (int k = 0; k < 16; ++k)
      random(k / 4, k % 4) = std::normal_distribution<double>(0.0, 1.0)(rng);
    const Eigen::Matrix4d qr = random.householderQr().householderQ();
    std::vector<Eigen::VectorXd> turned;
    for (const auto& x : pts)
      turned.push_back(qr * x);
    const BSplineCurve<So3> a(rot, m, u), b(left, m, u), c(right, m, u);
    const BSplineCurve<Sphere> s(pts, m, u), st(turned, m, u);
    for (double t : linspace(u[static_cast<std::size_t>(m)], u[n], 17))
    {
      EXPECT_LT(Space<So3>::distance(Quaternion<double>(h * a.value(t)), b.value(t)), 1e-12);
      EXPECT_LT(Space<So3>::distance(Quaternion<double>(a.value(t) * h), c.value(t)), 1e-12);
      EXPECT_LT((qr * s.value(t) - st.value(t)).norm(), 1e-12);
    }
  }
}

TYPED_TEST(AllGeometries, MovingOneControlPointChangesOnlyItsKnotSpans)
{
  // Control point d_i enters the m + 1 spans of [u_i, u_{i+m+1}]: outside it the curve is
  // bit-identical; at its two ends, from a side where the classical basis function N_{i,m}
  // vanishes, it is unchanged up to rounding (an interpolation at α = 1 reproduces its end
  // point only to a few ulps of the coordinates, here up to ~5 m); on each non-empty span
  // inside, it moves.
  using Sp = Space<TypeParam>;
  std::mt19937 rng(404);
  for (int m = 1; m <= 5; ++m)
    for (bool clamped : { true, false })
    {
      const std::size_t n = static_cast<std::size_t>(m) + 4;
      const std::size_t mm = static_cast<std::size_t>(m);
      const auto pts = Sp::polygon(rng, n);
      const auto u = randomKnots(rng, n, m, clamped);
      const BSplineCurve<TypeParam> base(pts, m, u);
      for (std::size_t i = 0; i < n; ++i)
      {
        auto moved = pts;
        const auto other = Sp::polygon(rng, 2);
        moved[i] = geodesic<TypeParam>(pts[i], other[1], 0.05);
        const BSplineCurve<TypeParam> c(moved, m, u);
        const double lo = u[i], hi = u[i + mm + 1];
        std::vector<double> ts = linspace(u[mm], u[n], 97);
        ts.insert(ts.end(), u.begin() + static_cast<std::ptrdiff_t>(mm), u.begin() + static_cast<std::ptrdiff_t>(n) + 1);
        for (double t : ts)
          for (Side side : { Side::kLeft, Side::kRight })
          {
            // At the domain's ends only the one-sided limit from inside exists.
            const Side inside = t >= u[n] ? Side::kLeft : t <= u[mm] ? Side::kRight : side;
            const double dist =
                Sp::distance(base.template evaluate<double>(t, side), c.template evaluate<double>(t, side));
            if (t < lo || t > hi)
            {
              EXPECT_EQ(dist, 0.0) << "i " << i << " t " << t << " degree " << m;
            }
            else if (basis(u, i, m, t, inside) == 0.0)  // at lo or hi, from a side where N_i vanishes
            {
              EXPECT_LE(dist, 1e-14) << "i " << i << " t " << t << " degree " << m;
            }
          }
        // Each non-empty span of [u_i, u_{i+m+1}] inside the domain moves at its midpoint.
        for (std::size_t k = std::max(i, mm); k < std::min(i + mm + 1, n); ++k)
          if (u[k] < u[k + 1])
          {
            const double t = 0.5 * (u[k] + u[k + 1]);
            EXPECT_GT(Sp::distance(base.value(t), c.value(t)), 1e-6) << "i " << i << " span " << k;
          }
      }
    }
}

// =======================================================================================
// 5. Knot vector validation
// =======================================================================================
namespace
{
/// The message of the InvalidInputError that building a B-spline with these knots throws
/// (empty if none is thrown).
std::string knotError(const std::vector<double>& u, std::size_t n, int m)
{
  std::mt19937 rng(501);
  const auto pts = randomPolygon(rng, n);
  try
  {
    const BSplineCurve<ScrewSe3> c(pts, m, u);
  }
  catch (const InvalidInputError& e)
  {
    return e.what();
  }
  return "";
}

bool contains(const std::string& s, const std::string& part)
{
  return s.find(part) != std::string::npos;
}
}  // namespace

TEST(KnotValidation, AcceptsValidKnotVectors)
{
  EXPECT_EQ(knotError(clampedUniformKnots(6, 3, 0.0, 2.0), 6, 3), "");
  EXPECT_EQ(knotError({ 0, 0, 0, 0, 1, 1, 1, 2, 2, 2, 2 }, 7, 3), "");  // interior multiplicity = degree
  EXPECT_EQ(knotError({ 0, 1, 2, 3, 4, 5, 6, 7, 8, 9 }, 6, 3), "");     // unclamped uniform
  EXPECT_EQ(knotError({ 0, 1, 1, 1, 2, 3, 4, 4 }, 5, 2), "");           // m + 1 equal knots at the start
  EXPECT_EQ(knotError(bezierKnots(4, -1.0, 1.0), 5, 4), "");
}

TEST(KnotValidation, RejectsWrongLengthNamingTheExpectedLength)
{
  // 5 control points of degree 3 need 5 + 3 + 1 = 9 knots.
  for (std::size_t length : { 0u, 8u, 10u })
  {
    std::vector<double> u(length);
    for (std::size_t i = 0; i < length; ++i)
      u[i] = static_cast<double>(i);
    const std::string msg = knotError(u, 5, 3);
    EXPECT_TRUE(contains(msg, "knots")) << msg;
    EXPECT_TRUE(contains(msg, "expected 9")) << msg;
    EXPECT_TRUE(contains(msg, "has " + std::to_string(length))) << msg;
  }
}

TEST(KnotValidation, RejectsNonFinite)
{
  for (double bad : { std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                      -std::numeric_limits<double>::infinity() })
  {
    std::vector<double> u = clampedUniformKnots(6, 3, 0.0, 1.0);
    u[5] = bad;
    const std::string msg = knotError(u, 6, 3);
    EXPECT_TRUE(contains(msg, "knots[5]")) << msg;
    EXPECT_TRUE(contains(msg, "finite")) << msg;
  }
}

TEST(KnotValidation, RejectsDecreasing)
{
  const std::string msg = knotError({ 0, 0, 0, 0, 0.6, 0.4, 1, 1, 1, 1 }, 6, 3);
  EXPECT_TRUE(contains(msg, "knots[5]")) << msg;
  EXPECT_TRUE(contains(msg, "non-decreasing")) << msg;
}

TEST(KnotValidation, RejectsInteriorMultiplicityAboveDegree)
{
  const std::string msg = knotError({ 0, 0, 0, 0, 0.5, 0.5, 0.5, 0.5, 1, 1, 1, 1 }, 8, 3);
  EXPECT_TRUE(contains(msg, "knots[4]")) << msg;
  EXPECT_TRUE(contains(msg, "multiplicity 4")) << msg;
  // More than m + 1 equal knots at an end.
  const std::string end = knotError({ 0, 0, 0, 0, 0, 1, 1, 1, 1 }, 5, 3);
  EXPECT_TRUE(contains(end, "knots[0]") && contains(end, "multiplicity 5")) << end;
}

TEST(KnotValidation, RejectsEmptyDomain)
{
  // n = 3, m = 2: domain [u_2, u_3] = [1, 1] although no knot repeats more than twice.
  const std::string msg = knotError({ 0, 0, 1, 1, 2, 2 }, 3, 2);
  EXPECT_TRUE(contains(msg, "knots")) << msg;
  EXPECT_TRUE(contains(msg, "empty")) << msg;
}

// =======================================================================================
// 6. Knot insertion (Boehm with geodesic interpolation; thesis ch. 6)
// =======================================================================================
TEST(KnotInsertion, EuclideanCurveIsUnchangedAndInsertionsCommute)
{
  std::mt19937 rng(601);
  for (int m = 1; m <= 5; ++m)
    for (bool clamped : { true, false })
      for (int trial = 0; trial < 6; ++trial)
      {
        const std::size_t n = static_cast<std::size_t>(m) + 2 + static_cast<std::size_t>(trial);
        const std::size_t mm = static_cast<std::size_t>(m);
        const auto pts = Space<Euclidean>::polygon(rng, n);
        const auto u = randomKnots(rng, n, m, clamped);
        const BSplineCurve<Euclidean> c(pts, m, u);
        // Candidates: random points of the domain and existing interior knots of multiplicity < m.
        std::uniform_real_distribution<double> in(u[mm], u[n]);
        std::vector<double> candidates{ in(rng), in(rng) };
        if (!clamped)  // the domain's start, at most m equal knots there yet
          candidates.push_back(u[mm]);
        for (double k : interiorKnots(u, n, m))
          if (std::count(u.begin(), u.end(), k) < m)
            candidates.push_back(k);
        for (double x : candidates)
        {
          const BSplineCurve<Euclidean> d = c.insertKnot(x);
          ASSERT_EQ(d.controlPoints().size(), n + 1);
          std::vector<double> expected_knots = u;
          expected_knots.insert(std::upper_bound(expected_knots.begin(), expected_knots.end(), x), x);
          EXPECT_EQ(d.knots(), expected_knots);
          for (double t : linspace(u[mm], u[n], 31))
          {
            const Eigen::VectorXd ref = classicalSpline(pts, u, m, t);
            EXPECT_LT((d.value(t) - ref).norm(), 1e-14 * std::max(1.0, ref.norm())) << "degree " << m << " t " << t;
          }
        }
        const double x = candidates[0], y = candidates[1];
        const auto xy = c.insertKnot(x).insertKnot(y).controlPoints();
        const auto yx = c.insertKnot(y).insertKnot(x).controlPoints();
        for (std::size_t i = 0; i < xy.size(); ++i)
          EXPECT_LT((xy[i] - yx[i]).norm(), 1e-14 * std::max(1.0, xy[i].norm()));
      }
}

namespace
{
struct InsertionFigures
{
  std::vector<double> moved;              // max pose distance curve before/after one insertion
  std::vector<double> moved_translation;  // its translation part (m)
  std::vector<double> moved_rotation;     // its rotation part (rad)
  std::vector<double> order_polygon;      // max pose distance between the polygons of x-then-y and y-then-x
  std::vector<double> order_curve;        // max pose distance between the two resulting curves
};

/// Random cubic splines of 8 control points (consecutive rotation `angle`, translation 1 m),
/// clamped uniform knots on [0, 1]; one knot inserted at a random place, and two knots in
/// the same random span inserted in both orders. Distances over 201 samples.
template <class G>
InsertionFigures measureInsertion(double angle, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const std::size_t n = 8;
  const int m = 3;
  const auto u = clampedUniformKnots(n, m, 0.0, 1.0);
  const std::vector<double> ts = linspace(0.0, 1.0, 201);
  InsertionFigures f;
  for (int trial = 0; trial < 100; ++trial)
  {
    const BSplineCurve<G> c(fixedStepPolygon(rng, n, angle, 1.0), m, u);
    const BSplineCurve<G> d = c.insertKnot(uni(rng));
    double moved = 0.0, mt = 0.0, mr = 0.0;
    for (double t : ts)
    {
      const Pose<double> a = c.value(t), b = d.value(t);
      moved = std::max(moved, poseDistance(a, b));
      mt = std::max(mt, (a.p - b.p).norm());
      mr = std::max(mr, rotationAngle(Quaternion<double>(a.q.conjugate() * b.q)));
    }
    f.moved.push_back(moved);
    f.moved_translation.push_back(mt);
    f.moved_rotation.push_back(mr);

    const double span = std::floor(uni(rng) * (n - m)) / (n - m);
    const double x = span + uni(rng) / (n - m), y = span + uni(rng) / (n - m);
    const BSplineCurve<G> xy = c.insertKnot(x).insertKnot(y), yx = c.insertKnot(y).insertKnot(x);
    double dp = 0.0, dc = 0.0;
    for (std::size_t i = 0; i < n + 2; ++i)
      dp = std::max(dp, poseDistance(xy.controlPoints()[i], yx.controlPoints()[i]));
    for (double t : ts)
      dc = std::max(dc, poseDistance(xy.value(t), yx.value(t)));
    f.order_polygon.push_back(dp);
    f.order_curve.push_back(dc);
  }
  return f;
}

void printFigures(const char* geometry, double angle, const InsertionFigures& f)
{
  auto row = [&](const char* what, const std::vector<double>& v) {
    std::printf("[figures] knot insertion, %s, cubic, 8 control points, steps %.1f rad / 1 m: %s: median %.3g, max %.3g\n",
                geometry, angle, what, median(v), *std::max_element(v.begin(), v.end()));
  };
  row("curve moved by one insertion (m + rad)", f.moved);
  row("  translation part (m)", f.moved_translation);
  row("  rotation part (rad)", f.moved_rotation);
  row("two insertion orders, control polygons differ by (m + rad)", f.order_polygon);
  row("two insertion orders, curves differ by (m + rad)", f.order_curve);
}
}  // namespace

TEST(KnotInsertion, OnSE3TheCurveMovesSlightlyAndOrderMatters)
{
  for (double angle : { 0.5, 1.0 })
  {
    const InsertionFigures screw = measureInsertion<ScrewSe3>(angle, 602);
    const InsertionFigures dbl = measureInsertion<DoubleGeodesicSe3>(angle, 602);
    printFigures("screw", angle, screw);
    printFigures("double_geodesic", angle, dbl);
    for (const InsertionFigures* f : { &screw, &dbl })
    {
      const double max_moved = *std::max_element(f->moved.begin(), f->moved.end());
      const double max_order = *std::max_element(f->order_curve.begin(), f->order_curve.end());
      // Bounds (about 3x the measured maxima): the insertion is a small perturbation.
      EXPECT_LT(max_moved, angle < 0.75 ? 1.5e-3 : 6e-3);
      EXPECT_LT(max_order, angle < 0.75 ? 1.5e-3 : 6e-3);
      // … but a real one: the group is not flat, the curve does move and the order matters.
      EXPECT_GT(median(f->moved), 1e-5);
      EXPECT_GT(median(f->order_polygon), 1e-6);
    }
    // The product metric's R³ factor is flat: translations are the classical spline, unchanged.
    EXPECT_LT(*std::max_element(dbl.moved_translation.begin(), dbl.moved_translation.end()), 1e-14);
  }
}

// =======================================================================================
// 7. Analytic derivatives
// =======================================================================================
namespace
{
void expectKinematicsNear(const Kinematics& a, const Kinematics& f, double tol, const std::string& where)
{
  EXPECT_LT(relError(a.velocity.linear, f.velocity.linear), tol) << where;
  EXPECT_LT(relError(a.velocity.angular, f.velocity.angular), tol) << where;
  EXPECT_LT(relError(a.acceleration.linear, f.acceleration.linear), tol) << where;
  EXPECT_LT(relError(a.acceleration.angular, f.acceleration.angular), tol) << where;
}
}  // namespace

TYPED_TEST(SE3Test, AnalyticDerivativesMatchCentralDifferences)
{
  std::mt19937 rng(701);
  const double h = 2e-4;
  for (int m = 1; m <= 5; ++m)
    for (int trial = 0; trial < 4; ++trial)
    {
      const std::size_t n = static_cast<std::size_t>(m) + 2 + static_cast<std::size_t>(trial);
      const std::size_t mm = static_cast<std::size_t>(m);
      const auto pts = randomPolygon(rng, n);
      const auto u = randomKnots(rng, n, m, trial % 2 == 0);
      const BSplineCurve<TypeParam> c(pts, m, u);
      const auto f = [&](double s) { return c.value(s); };
      // Inside the spans, and just beside every interior knot (the stencil, ±2h, stays on one side).
      std::uniform_real_distribution<double> in(u[mm] + 3 * h, u[n] - 3 * h);
      std::vector<double> ts{ in(rng), in(rng), in(rng) };
      for (double k : interiorKnots(u, n, m))
      {
        ts.push_back(k - 2.5 * h);
        ts.push_back(k + 2.5 * h);
      }
      for (double t : ts)
        expectKinematicsNear(kinematicsAt(c, t), test::centralDifferences(f, t, h), 1e-6,
                             "degree " + std::to_string(m) + " t " + std::to_string(t));
      // Exactly at the interior knots: each one-sided derivative is that of the adjacent
      // polynomial piece (de Boor on the fixed span, continued past the knot).
      const auto logs = polygonLogs<TypeParam>(pts, "d");
      for (double k : interiorKnots(u, n, m))
      {
        const std::size_t first = static_cast<std::size_t>(std::lower_bound(u.begin(), u.end(), k) - u.begin());
        const std::size_t last = static_cast<std::size_t>(std::upper_bound(u.begin(), u.end(), k) - u.begin()) - 1;
        const auto left = [&](double s) { return deBoor<TypeParam>(pts, logs, u, m, first - 1, s); };
        const auto right = [&](double s) { return deBoor<TypeParam>(pts, logs, u, m, last, s); };
        expectKinematicsNear(kinematicsAt(c, k, Side::kLeft), test::centralDifferences(left, k, h), 1e-6,
                             "left of knot " + std::to_string(k) + ", degree " + std::to_string(m));
        expectKinematicsNear(kinematicsAt(c, k, Side::kRight), test::centralDifferences(right, k, h), 1e-6,
                             "right of knot " + std::to_string(k) + ", degree " + std::to_string(m));
      }
    }
}

namespace
{
/// Largest left/right differences of velocity and of acceleration (relative, floor 1) at the
/// knots `at` of a curve.
template <class G>
std::pair<double, double> jumps(const BSplineCurve<G>& c, const std::vector<double>& at)
{
  double dv = 0.0, da = 0.0;
  for (double k : at)
  {
    const Kinematics l = kinematicsAt(c, k, Side::kLeft), r = kinematicsAt(c, k, Side::kRight);
    EXPECT_LT(poseDistance(l.pose, r.pose), 1e-13);
    dv = std::max({ dv, relError(l.velocity.linear, r.velocity.linear), relError(l.velocity.angular, r.velocity.angular) });
    da = std::max({ da, relError(l.acceleration.linear, r.acceleration.linear),
                    relError(l.acceleration.angular, r.acceleration.angular) });
  }
  return { dv, da };
}

/// Simple knots at 1, 2.5 and 3, a double knot at 4.2 (9 control points, cubic).
const std::vector<double> kCubicKnots{ 0, 0, 0, 0, 1, 2.5, 3, 4.2, 4.2, 5, 5, 5, 5 };
}  // namespace

TYPED_TEST(SE3Test, AbelianCubicIsC2AtSimpleKnotsAndC1AtADoubleKnot)
{
  // Pure translations, and rotations about one fixed axis: the classical C^{m−μ}.
  std::mt19937 rng(702);
  std::normal_distribution<double> d(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial)
  {
    const Eigen::Vector3d axis = randomUnitVector<3>(rng);
    std::vector<Pose<double>> translations, rotations;
    double angle = 0.0;
    for (int i = 0; i < 9; ++i)
    {
      translations.emplace_back(Quaternion<double>::Identity(), Eigen::Vector3d(d(rng), d(rng), d(rng)));
      angle += d(rng);
      rotations.emplace_back(so3Exp<double>(angle * axis), Eigen::Vector3d::Zero());
    }
    for (const auto* pts : { &translations, &rotations })
    {
      const BSplineCurve<TypeParam> c(*pts, 3, kCubicKnots);
      const auto simple = jumps(c, { 1.0, 2.5, 3.0 });
      const auto dbl = jumps(c, { 4.2 });
      EXPECT_LT(simple.first, 1e-12);
      EXPECT_LT(simple.second, 1e-12);
      EXPECT_LT(dbl.first, 1e-12);
      EXPECT_GT(dbl.second, 1e-3);
    }
  }
}

TYPED_TEST(SE3Test, CubicIsC1EverywhereButOnlyNearlyC2OnTheCurvedGroup)
{
  // On SE(3) the generalised de Boor cubic is C¹ at simple knots, but the acceleration jumps
  // slightly: a curvature (commutator) effect of third order in the size of the control
  // polygon's steps (halving every step, rotation and translation, divides it by ~8) that
  // vanishes in the abelian cases above. At a double knot the acceleration jump is O(1).
  std::mt19937 rng(703);
  std::array<double, 2> worst_jump{}, largest_accel{};
  const std::array<double, 2> steps{ 0.5, 0.25 };
  double smallest_double_jump = std::numeric_limits<double>::infinity();
  for (int trial = 0; trial < 30; ++trial)
  {
    const std::uint32_t seed = rng();
    for (std::size_t s = 0; s < steps.size(); ++s)
    {
      std::mt19937 same(seed);  // the same directions for both step sizes
      const BSplineCurve<TypeParam> c(fixedStepPolygon(same, 9, steps[s], steps[s]), 3, kCubicKnots);
      const auto simple = jumps(c, { 1.0, 2.5, 3.0 });
      const auto dbl = jumps(c, { 4.2 });
      EXPECT_LT(simple.first, 1e-12);
      EXPECT_LT(dbl.first, 1e-12);
      for (double k : { 1.0, 2.5, 3.0 })
      {
        const Kinematics l = kinematicsAt(c, k, Side::kLeft), r = kinematicsAt(c, k, Side::kRight);
        worst_jump[s] = std::max({ worst_jump[s], (l.acceleration.linear - r.acceleration.linear).norm(),
                                   (l.acceleration.angular - r.acceleration.angular).norm() });
        largest_accel[s] = std::max({ largest_accel[s], l.acceleration.linear.norm(), l.acceleration.angular.norm() });
      }
      smallest_double_jump = std::min(smallest_double_jump, dbl.second);
    }
  }
  std::printf("[figures] cubic B-spline, %s, acceleration jump at simple knots (steps 0.5 rad / 0.5 m): "
              "max %.3g (largest |acceleration| %.3g); steps 0.25: max %.3g (%.3g)\n",
              std::is_same<TypeParam, ScrewSe3>::value ? "screw" : "double_geodesic", worst_jump[0], largest_accel[0],
              worst_jump[1], largest_accel[1]);
  EXPECT_GT(worst_jump[0], 1e-6);                      // not C²…
  EXPECT_LT(worst_jump[0], 0.01 * largest_accel[0]);  // … but nearly
  EXPECT_GT(worst_jump[0] / worst_jump[1], 6.0);      // third order in the step
  EXPECT_LT(worst_jump[0] / worst_jump[1], 10.0);
  EXPECT_GT(smallest_double_jump, 1e-3);
}

TYPED_TEST(SE3Test, DeBoorIsRepeatedKnotInsertion)
{
  // Inserting t m times reproduces the de Boor triangle (thesis ch. 6): the control point of
  // index k (t in span k) is then the curve's value at t, on the group as in R^n.
  std::mt19937 rng(704);
  for (int m = 1; m <= 5; ++m)
    for (int trial = 0; trial < 4; ++trial)
    {
      const std::size_t n = static_cast<std::size_t>(m) + 2 + static_cast<std::size_t>(trial);
      const std::size_t mm = static_cast<std::size_t>(m);
      const auto u = randomKnots(rng, n, m, trial % 2 == 0);
      const BSplineCurve<TypeParam> c(randomPolygon(rng, n), m, u);
      const double t = std::uniform_real_distribution<double>(u[mm], u[n])(rng);
      const std::size_t k = static_cast<std::size_t>(std::upper_bound(u.begin(), u.end(), t) - u.begin()) - 1;
      BSplineCurve<TypeParam> d = c;
      for (int r = 0; r < m; ++r)
        d = d.insertKnot(t);
      EXPECT_LT(poseDistance(d.controlPoints()[k], c.value(t)), 1e-12) << "degree " << m;
    }
}

TEST(DomainEnds, RepeatedKnotAtADomainEndIsEvaluatedFromInside)
{
  // u_{N−1} = u_N (the end knot repeated m + 1 times, unclamped start) and u_m = u_{m+1}
  // (the start knot repeated inside the domain): the span clamped to the domain is empty
  // there, the value is the one-sided limit from inside, and measureCurve stays finite.
  std::mt19937 rng(705);
  const int m = 2;
  for (const std::vector<double>& u : { std::vector<double>{ 0, 1, 2, 3, 4, 4, 4, 5 },
                                        std::vector<double>{ 0, 1, 1, 1, 2, 3, 4, 5 } })
  {
    const auto pts = Space<Euclidean>::polygon(rng, 5);
    const BSplineCurve<Euclidean> c(pts, m, u);
    for (double t : { u[2], u[5] })
      for (Side side : { Side::kLeft, Side::kRight })
      {
        const Eigen::VectorXd ref = classicalSpline(pts, u, m, t);
        const Eigen::VectorXd x = c.evaluate<double>(t, side);
        EXPECT_LT((x - ref).norm(), 1e-14) << "t " << t;
      }
    const BSplineCurve<ScrewSe3> s(randomPolygon(rng, 5), m, u);
    const Kinematics start = kinematicsAt(s, u[2], Side::kLeft), end = kinematicsAt(s, u[5], Side::kRight);
    EXPECT_TRUE(start.velocity.linear.allFinite() && start.acceleration.angular.allFinite());
    EXPECT_TRUE(end.velocity.linear.allFinite() && end.acceleration.angular.allFinite());
    const CurveFigures f = measureCurve(s, 1.0);
    EXPECT_TRUE(std::isfinite(f.length) && std::isfinite(f.energy) && std::isfinite(f.max_angular_acceleration));
  }
}

// =======================================================================================
// 8. Boundary derivatives: thesis Prop. 4.2.8 / 4.2.9, Crouch et al. Thm 2.5 / 2.9
// =======================================================================================
namespace
{
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// The body velocity in the geometry's tangent representation: (Rᵀω, Rᵀṗ) for the screw
/// geometry (the body twist), (Rᵀω, ṗ) for the product metric.
template <class G>
Vector6<double> tangentVelocity(const Kinematics& k)
{
  const Eigen::Matrix3d rt = k.pose.q.toRotationMatrix().transpose();
  Vector6<double> v;
  v << rt * k.velocity.angular,
      std::is_same<G, ScrewSe3>::value ? Eigen::Vector3d(rt * k.velocity.linear) : k.velocity.linear;
  return v;
}

/// ∫_0^1 exp(s A) ds = Σ A^k/(k + 1)!.
template <int D>
Eigen::Matrix<double, D, D> integralOfExp(const Eigen::Matrix<double, D, D>& a)
{
  using M = Eigen::Matrix<double, D, D>;
  M sum = M::Identity(), term = M::Identity();
  for (int k = 1; k < 60; ++k)
  {
    term = term * a / static_cast<double>(k + 1);
    sum += term;
  }
  return sum;
}

/// ad_ξ on se(3), ξ = (ω, v): [ξ, η] = (ω × ω', ω × v' − ω' × v).
Matrix6d adSe3(const Vector6<double>& xi)
{
  Matrix6d a = Matrix6d::Zero();
  a.topLeftCorner<3, 3>() = hat<double>(xi.head<3>());
  a.bottomRightCorner<3, 3>() = hat<double>(xi.head<3>());
  a.bottomLeftCorner<3, 3>() = hat<double>(xi.tail<3>());
  return a;
}

/// Υ(A) W = (∫_0^1 exp(s A) ds)⁻¹ W.
template <int D>
Eigen::Matrix<double, D, 1> upsilon(const Eigen::Matrix<double, D, D>& a, const Eigen::Matrix<double, D, 1>& w)
{
  return integralOfExp<D>(a).lu().solve(w);
}

/// Body and spatial twists and their time derivatives of a pose curve from its jet:
/// body (Rᵀω, Rᵀṗ), spatial (ω, ṗ − ω × p) (so that ġ = g Ω_b = Ω_s g as 4×4 matrices).
struct Twists
{
  Vector6<double> body, body_rate, spatial, spatial_rate;
};
Twists twistsOf(const Kinematics& k)
{
  const Eigen::Matrix3d rt = k.pose.q.toRotationMatrix().transpose();
  const Eigen::Vector3d &w = k.velocity.angular, &pd = k.velocity.linear, &wd = k.acceleration.angular,
                        &pdd = k.acceleration.linear, &p = k.pose.p;
  Twists t;
  t.body << rt * w, rt * pd;
  t.body_rate << rt * wd, rt * pdd - (rt * w).cross(rt * pd);
  t.spatial << w, pd - w.cross(p);
  t.spatial_rate << wd, pdd - wd.cross(p) - w.cross(pd);
  return t;
}

/// Body and spatial angular velocity rates of a rotation curve from its jet.
void rotationRates(const Quaternion<Jet<2>>& q, Eigen::Vector3d* body_rate, Eigen::Vector3d* spatial_rate)
{
  const Quaternion<double> q0(q.w().value(), q.x().value(), q.y().value(), q.z().value());
  const Quaternion<double> c2(q.w().coefficient(2), q.x().coefficient(2), q.y().coefficient(2),
                              q.z().coefficient(2));
  // ω_b = 2 vec(q̄ q̇), ω̇_b = 2 vec(q̄ q̈) (q̄̇ q̇ = |q̇|² is real), q̈ = 2 c₂; likewise spatially.
  *body_rate = 4.0 * (q0.conjugate() * c2).vec();
  *spatial_rate = 4.0 * (c2 * q0.conjugate()).vec();
}
}  // namespace

TYPED_TEST(SE3Test, ClampedBSplineEndVelocitiesFollowProposition428)
{
  // Start: d/dt = m/(u_{m+1} − u_1) Log(d_0, d_1) (body form at d_0); end: m/(u_{N+m−1} − u_{N−1})
  // Log(d_{N−2}, d_{N−1}) at d_{N−1}. Bézier knots on [0, 1] give n V_0^1 and n V_{n−1}^1.
  std::mt19937 rng(801);
  for (int m = 1; m <= 5; ++m)
    for (int trial = 0; trial < 6; ++trial)
    {
      const std::size_t n = static_cast<std::size_t>(m) + 1 + static_cast<std::size_t>(trial);
      const std::size_t mm = static_cast<std::size_t>(m);
      const auto pts = randomPolygon(rng, n);
      const auto u = trial == 0 ? bezierKnots(m, 0.0, 1.0) : randomKnots(rng, n, m, true, 0.7);
      const BSplineCurve<TypeParam> c(pts, m, u);
      const Vector6<double> v0 = m / (u[mm + 1] - u[1]) * TypeParam::log(pts[0], pts[1]);
      const Vector6<double> v1 = m / (u[n + mm - 1] - u[n - 1]) * TypeParam::log(pts[n - 2], pts[n - 1]);
      const Vector6<double> a0 = tangentVelocity<TypeParam>(kinematicsAt(c, u[mm], Side::kRight));
      const Vector6<double> a1 = tangentVelocity<TypeParam>(kinematicsAt(c, u[n], Side::kLeft));
      EXPECT_LT((a0 - v0).norm(), 1e-12 * std::max(1.0, v0.norm())) << "degree " << m;
      EXPECT_LT((a1 - v1).norm(), 1e-12 * std::max(1.0, v1.norm())) << "degree " << m;
    }
}

TEST(BoundaryAcceleration, ScrewBezierFollowsCrouchTheorem29)
{
  // For a bi-invariant metric the covariant acceleration is Ω̇, with Ω the body (ġ = g Ω_b)
  // or spatial (ġ = Ω_s g) velocity. With V_k = Log(g_k⁻¹ g_{k+1}) (thesis, body) and
  // W_k = Log(g_{k+1} g_k⁻¹) (Crouch eq. 4, spatial), n = degree:
  //   Ω̇_s(0) = n(n−1) (∫exp(u ad W_0))⁻¹ (W_1 − W_0),   Ω̇_s(1) = n(n−1) (∫exp(−u ad W_{n−1}))⁻¹ (W_{n−1} − W_{n−2})
  //   Ω̇_b(0) = n(n−1) (∫exp(−u ad V_0))⁻¹ (V_1 − V_0),   Ω̇_b(1) = n(n−1) (∫exp(u ad V_{n−1}))⁻¹ (V_{n−1} − V_{n−2})
  // Crouch's spatial statement holds as printed; the thesis' body form (Prop. 4.2.9) copies
  // its operators and needs the sign of ad flipped at both ends: checked to fail as printed.
  std::mt19937 rng(802);
  double worst = 0.0, best_printed = std::numeric_limits<double>::infinity();
  for (int trial = 0; trial < 10; ++trial)
    for (std::size_t count = 3; count <= 7; ++count)
    {
      const double n = static_cast<double>(count) - 1;
      const auto g = randomPolygon(rng, count, 1.0);
      const BezierCurve<ScrewSe3> c(g, 0.0, 1.0);
      std::vector<Vector6<double>> v, w;
      for (std::size_t k = 0; k + 1 < count; ++k)
      {
        v.push_back(se3Log(g[k].inverse() * g[k + 1]));
        w.push_back(se3Log(g[k + 1] * g[k].inverse()));
      }
      const std::size_t e = count - 2;
      const Twists s = twistsOf(kinematicsAt(c, 0.0)), f = twistsOf(kinematicsAt(c, 1.0, Side::kLeft));
      const std::array<std::pair<Vector6<double>, Vector6<double>>, 4> checks{ {
          { s.spatial_rate, n * (n - 1) * upsilon<6>(adSe3(w[0]), w[1] - w[0]) },
          { f.spatial_rate, n * (n - 1) * upsilon<6>(-adSe3(w[e]), w[e] - w[e - 1]) },
          { s.body_rate, n * (n - 1) * upsilon<6>(-adSe3(v[0]), v[1] - v[0]) },
          { f.body_rate, n * (n - 1) * upsilon<6>(adSe3(v[e]), v[e] - v[e - 1]) },
      } };
      for (const auto& c2 : checks)
        worst = std::max(worst, (c2.first - c2.second).norm() / std::max(1.0, c2.second.norm()));
      // The thesis' printed body form: + at t = 0, − at t = 1.
      const Vector6<double> printed0 = n * (n - 1) * upsilon<6>(adSe3(v[0]), v[1] - v[0]);
      const Vector6<double> printed1 = n * (n - 1) * upsilon<6>(-adSe3(v[e]), v[e] - v[e - 1]);
      best_printed = std::min({ best_printed, (s.body_rate - printed0).norm() / printed0.norm(),
                                (f.body_rate - printed1).norm() / printed1.norm() });
      // Theorem 2.5 (first derivative) alongside: Ω_b(0) = n V_0, Ω_s(1) = n W_{n−1}.
      EXPECT_LT((s.body - n * v[0]).norm(), 1e-12 * std::max(1.0, n * v[0].norm()));
      EXPECT_LT((f.spatial - n * w[e]).norm(), 1e-12 * std::max(1.0, n * w[e].norm()));
    }
  EXPECT_LT(worst, 1e-10);
  EXPECT_GT(best_printed, 1e-3);
}

TEST(BoundaryAcceleration, So3BezierFollowsCrouchTheorem29)
{
  std::mt19937 rng(803);
  double worst = 0.0, best_printed = std::numeric_limits<double>::infinity();
  for (int trial = 0; trial < 10; ++trial)
    for (std::size_t count = 3; count <= 7; ++count)
    {
      const double n = static_cast<double>(count) - 1;
      const auto g = Space<So3>::polygon(rng, count);
      const BezierCurve<So3> c(g, 0.0, 1.0);
      std::vector<Eigen::Vector3d> v, w;
      for (std::size_t k = 0; k + 1 < count; ++k)
      {
        v.push_back(so3Log(Quaternion<double>(g[k].conjugate() * g[k + 1])));
        w.push_back(so3Log(Quaternion<double>(g[k + 1] * g[k].conjugate())));
      }
      const std::size_t e = count - 2;
      Eigen::Vector3d b0, s0, b1, s1;
      rotationRates(c.jet(Jet<2>::variable(0.0), Side::kRight), &b0, &s0);
      rotationRates(c.jet(Jet<2>::variable(1.0), Side::kLeft), &b1, &s1);
      const std::array<std::pair<Eigen::Vector3d, Eigen::Vector3d>, 4> checks{ {
          { s0, n * (n - 1) * upsilon<3>(hat<double>(w[0]), w[1] - w[0]) },
          { s1, n * (n - 1) * upsilon<3>(-hat<double>(w[e]), w[e] - w[e - 1]) },
          { b0, n * (n - 1) * upsilon<3>(-hat<double>(v[0]), v[1] - v[0]) },
          { b1, n * (n - 1) * upsilon<3>(hat<double>(v[e]), v[e] - v[e - 1]) },
      } };
      for (const auto& c2 : checks)
        worst = std::max(worst, (c2.first - c2.second).norm() / std::max(1.0, c2.second.norm()));
      const Eigen::Vector3d printed0 = n * (n - 1) * upsilon<3>(hat<double>(v[0]), v[1] - v[0]);
      const Eigen::Vector3d printed1 = n * (n - 1) * upsilon<3>(-hat<double>(v[e]), v[e] - v[e - 1]);
      best_printed = std::min({ best_printed, (b0 - printed0).norm() / printed0.norm(),
                                (b1 - printed1).norm() / printed1.norm() });
    }
  EXPECT_LT(worst, 1e-10);
  EXPECT_GT(best_printed, 1e-3);
}
