// Pobegailo's blending polynomials (Pobegailo §3–4) and the C^n blended spline (§5–7) in every
// geometry of the core: boundary conditions, energy minimality, interpolation, C^n (and not
// C^{n+1}) at the waypoints, locality, the classical Euclidean formula, and Pobegailo's own
// circle splines on S² with his knot rule, each against an independent test-side computation.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/curves/blended_spline.h"
#include "se3_interpolation/planner/curve_factory.h"
#include "se3_interpolation/planner/planner.h"
#include "allocation_counter.h"
#include "test_utils.h"

using namespace se3_interpolation;

namespace
{
constexpr double kPi = 3.14159265358979323846;

double binomial(int n, int k)
{
  double r = 1.0;
  for (int i = 1; i <= k; ++i)
    r = r * (n - k + i) / i;
  return r;
}

double factorialRatio(int a, int b)  // a!/b!
{
  double r = 1.0;
  for (int i = b + 1; i <= a; ++i)
    r *= i;
  return r;
}

/// Test-side Bézier polynomial Σ c_j C(d, j) (1 − u)^{d−j} u^j with std::pow.
double bernsteinPow(const std::vector<double>& c, double u)
{
  const int d = static_cast<int>(c.size()) - 1;
  double s = 0.0;
  for (int j = 0; j <= d; ++j)
    s += c[j] * binomial(d, j) * std::pow(1.0 - u, d - j) * std::pow(u, j);
  return s;
}

/// The control values of eqs. 3.1 and 4.1 written out from the sums over i.
std::vector<double> controlW1(int n)
{
  std::vector<double> c(2 * n + 2, 0.0);
  for (int i = 1; i <= n + 1; ++i)
    c[n + i] = (n + i) / (2.0 * n + 1.0);
  return c;
}
std::vector<double> controlW2(int n)
{
  std::vector<double> c(2 * n + 2, 0.0);
  for (int i = 1; i <= n; ++i)
    c[i] = i / (2.0 * n + 1.0);
  return c;
}

double testW1(int n, double u)
{
  if (n == 1)
    return 2 * (1 - u) * u * u + u * u * u;  // the paper's explicit forms (§3)
  if (n == 2)
    return 6 * std::pow(1 - u, 2) * std::pow(u, 3) + 4 * (1 - u) * std::pow(u, 4) + std::pow(u, 5);
  return bernsteinPow(controlW1(n), u);
}
double testW2(int n, double u)
{
  if (n == 1)
    return (1 - u) * (1 - u) * u;  // §4
  if (n == 2)
    return std::pow(1 - u, 4) * u + 4 * std::pow(1 - u, 3) * u * u;  // §4 as corrected (see curves/blended_spline.h)
  return bernsteinPow(controlW2(n), u);
}

// ---- Geometry configurations for the typed tests ------------------------------------------

std::vector<double> randomTimes(std::mt19937& rng, std::size_t n)
{
  std::uniform_real_distribution<double> gap(0.5, 2.0);
  std::vector<double> t{ std::uniform_real_distribution<double>(-1.0, 1.0)(rng) };
  for (std::size_t i = 1; i < n; ++i)
    t.push_back(t.back() + gap(rng));
  return t;
}

/// A random walk on S^m that keeps turning gently (no near-reversals).
std::vector<Eigen::VectorXd> randomSpherePath(std::mt19937& rng, std::size_t n, int dim)
{
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> step(0.3, 0.9);
  Eigen::VectorXd x = test::randomUnitVectorX(rng, dim);
  Eigen::VectorXd d(dim);
  for (int i = 0; i < dim; ++i)
    d[i] = g(rng);
  std::vector<Eigen::VectorXd> p{ x };
  for (std::size_t k = 1; k < n; ++k)
  {
    Eigen::VectorXd noise(dim);
    for (int i = 0; i < dim; ++i)
      noise[i] = g(rng);
    d = d.normalized() + 0.6 * noise.normalized();
    d -= d.dot(x) * x;
    d.normalize();
    x = Sphere::exp<double>(x, Eigen::VectorXd(step(rng) * d));
    p.push_back(x);
  }
  return p;
}

struct ScrewConfig
{
  using G = ScrewSe3;
  static constexpr int kQuaternion = 4;
  static std::vector<Pose<double>> points(std::mt19937& rng, std::size_t n) { return test::randomPolygon(rng, n); }
  static double distance(const Pose<double>& a, const Pose<double>& b) { return test::poseDistance(a, b); }
};
struct DoubleGeodesicConfig : ScrewConfig
{
  using G = DoubleGeodesicSe3;
};
struct So3Config
{
  using G = So3;
  static constexpr int kQuaternion = 4;
  static std::vector<Quaternion<double>> points(std::mt19937& rng, std::size_t n)
  {
    std::vector<Quaternion<double>> q;
    for (const auto& p : test::randomPolygon(rng, n))
      q.push_back(p.q);
    return q;
  }
  static double distance(const Quaternion<double>& a, const Quaternion<double>& b)
  {
    return rotationAngle(Quaternion<double>(a.conjugate() * b));
  }
};
struct EuclideanConfig
{
  using G = Euclidean;
  static constexpr int kQuaternion = 0;
  static std::vector<Eigen::VectorXd> points(std::mt19937& rng, std::size_t n)
  {
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<Eigen::VectorXd> p;
    for (std::size_t i = 0; i < n; ++i)
      p.push_back(Eigen::Vector3d(g(rng), g(rng), g(rng)));
    return p;
  }
  static double distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm(); }
};
template <int Dim>
struct SphereConfig
{
  using G = Sphere;
  static constexpr int kQuaternion = 0;
  static std::vector<Eigen::VectorXd> points(std::mt19937& rng, std::size_t n)
  {
    return randomSpherePath(rng, n, Dim);
  }
  static double distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm(); }
};

template <int K>
std::vector<Jet<K>> flatten(const Pose<Jet<K>>& x)
{
  return { x.q.x(), x.q.y(), x.q.z(), x.q.w(), x.p.x(), x.p.y(), x.p.z() };
}
template <int K>
std::vector<Jet<K>> flatten(const Quaternion<Jet<K>>& q)
{
  return { q.x(), q.y(), q.z(), q.w() };
}
template <int K>
std::vector<Jet<K>> flatten(const VectorX<Jet<K>>& v)
{
  return std::vector<Jet<K>>(v.data(), v.data() + v.size());
}

/// Largest difference of the k-th derivatives of two flattened jets, and their scale; the
/// quaternion block (first `nq` entries) of `b` is sign-aligned with `a` (q ~ −q).
template <int K>
void compareOrder(std::vector<Jet<K>> a, std::vector<Jet<K>> b, int nq, int k, double* diff, double* scale)
{
  double dot = 0.0;
  for (int j = 0; j < nq; ++j)
    dot += a[j].value() * b[j].value();
  if (dot < 0.0)
    for (int j = 0; j < nq; ++j)
      b[j] = -b[j];
  *diff = 0.0;
  *scale = 1.0;
  for (std::size_t j = 0; j < a.size(); ++j)
  {
    *diff = std::max(*diff, std::abs(a[j].derivative(k) - b[j].derivative(k)));
    *scale = std::max(*scale, std::abs(a[j].derivative(k)));
  }
}

template <class Config>
class BlendedTest : public ::testing::Test
{
};
using Configs = ::testing::Types<ScrewConfig, DoubleGeodesicConfig, So3Config, EuclideanConfig, SphereConfig<3>,
                                 SphereConfig<5>>;
TYPED_TEST_SUITE(BlendedTest, Configs);

/// Checks C^n and not C^{n+1} at every interior waypoint with jets of order n + 1: derivatives of
/// order k ≤ n agree to 1e-8 relative for k ≤ 4 (to 1e-4 above: the Taylor coefficients of the
/// degree-(2n+1) blending polynomials cancel, losing about one digit per order — measured 3e-8 at
/// order 6 and 8e-6 at order 8), while order n + 1 jumps by more than 1e-3 relative (measured
/// ≥ 0.03).
template <class Config, int N>
void checkContinuity(std::mt19937& rng, std::size_t num_points)
{
  using G = typename Config::G;
  const auto x = Config::points(rng, num_points);
  const auto t = randomTimes(rng, num_points);
  const BlendedSpline<G> c(x, t, N);
  for (std::size_t i = 1; i + 1 < num_points; ++i)
  {
    const auto left = flatten(c.template evaluate<Jet<N + 1>>(Jet<N + 1>::variable(t[i]), Side::kLeft));
    const auto right = flatten(c.template evaluate<Jet<N + 1>>(Jet<N + 1>::variable(t[i]), Side::kRight));
    for (int k = 0; k <= N; ++k)
    {
      double diff, scale;
      compareOrder(left, right, Config::kQuaternion, k, &diff, &scale);
      EXPECT_LE(diff, (k <= 4 ? 1e-8 : 1e-4) * scale) << "n = " << N << ", waypoint " << i << ", derivative " << k;
    }
    double diff, scale;
    compareOrder(left, right, Config::kQuaternion, N + 1, &diff, &scale);
    EXPECT_GT(diff, 1e-3 * scale) << "n = " << N << ", waypoint " << i << ": derivative " << N + 1
                                  << " unexpectedly continuous";
  }
}
}  // namespace

// ---- Blending polynomials ------------------------------------------------------------------

TEST(BlendingPolynomials, EqualThePapersBernsteinSumsAndExplicitForms)
{
  for (int n = 1; n <= 8; ++n)
    for (double u : { 0.0, 0.05, 0.3, 0.5, 0.61, 0.9, 1.0, -0.2, 1.3 })
    {
      EXPECT_NEAR(blendingW1(n, u), testW1(n, u), 1e-13) << n << " " << u;
      EXPECT_NEAR(blendingW2(n, u), testW2(n, u), 1e-13) << n << " " << u;
      // The control values of u are j/(2n+1); outside [0, 1] the Bernstein sum's condition number
      // (|u| + |1 − u|)^{2n+1} scales the rounding error.
      EXPECT_NEAR(blendingW1(n, u) + blendingW2(n, u), u, 1e-14 * std::pow(std::abs(u) + std::abs(1 - u), 2 * n + 1));
    }
}

TEST(BlendingPolynomials, BoundaryConditions)
{
  // Eqs. 3.2–3.5 and 4.2–4.5 with exact derivatives (jets of order 9 cover n ≤ 8), including the
  // derivative formulas 3.4 and 4.3 evaluated from their binomial sums; and order n + 1 is not
  // flat (the conditions are sharp).
  for (int n = 1; n <= 8; ++n)
  {
    const int d = 2 * n + 1;
    const BlendingPolynomial w1 = BlendingPolynomial::increasing(n);
    const BlendingPolynomial w2 = BlendingPolynomial::decreasing(n);
    const Jet<9> a1 = w1(Jet<9>::variable(0.0)), b1 = w1(Jet<9>::variable(1.0));
    const Jet<9> a2 = w2(Jet<9>::variable(0.0)), b2 = w2(Jet<9>::variable(1.0));
    EXPECT_EQ(a1.value(), 0.0);  // 3.2
    EXPECT_NEAR(b1.value(), 1.0, 1e-15);
    EXPECT_EQ(a2.value(), 0.0);  // 4.2
    EXPECT_NEAR(b2.value(), 0.0, 1e-15);
    for (int m = 1; m <= n; ++m)
    {
      const double scale = factorialRatio(d, d - m);
      double eq34 = 0.0, eq43 = 0.0;
      for (int i = 0; i <= m; ++i)
      {
        eq34 += std::pow(-1.0, i) * binomial(m, i) * (d - i) / d;
        eq43 += std::pow(-1.0, m - i) * binomial(m, i) * i / d;
      }
      eq34 *= scale;
      eq43 *= scale;
      const double expected_end = m == 1 ? 1.0 : 0.0;  // 3.5 and 4.5
      EXPECT_NEAR(eq34, expected_end, 1e-9 * scale);
      EXPECT_NEAR(eq43, expected_end, 1e-9 * scale);
      EXPECT_NEAR(a1.derivative(m), 0.0, 1e-9 * scale) << "3.3 n=" << n << " m=" << m;
      EXPECT_NEAR(b1.derivative(m), eq34, 1e-9 * scale) << "3.4 n=" << n << " m=" << m;
      EXPECT_NEAR(a2.derivative(m), eq43, 1e-9 * scale) << "4.3 n=" << n << " m=" << m;
      EXPECT_NEAR(b2.derivative(m), 0.0, 1e-9 * scale) << "4.4 n=" << n << " m=" << m;
    }
    if (n + 1 <= 9)
    {
      const double scale = factorialRatio(d, d - n - 1);
      EXPECT_GT(std::abs(a1.derivative(n + 1)), 1e-3 * scale) << n;
      EXPECT_GT(std::abs(b2.derivative(n + 1)), 1e-3 * scale) << n;
    }
  }
}

namespace
{
/// J_n(f) = ∫_0^1 |f^{(n+1)}|² du by composite 8-point Gauss–Legendre (exact to rounding for
/// these polynomials), and the cross term ∫ f^{(n+1)} g^{(n+1)} du.
template <class F, class H>
void energy(int n, const F& f, const H& g, double* jf, double* cross)
{
  static const double kNodes[8] = { -0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                    -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                    0.7966664774136267,  0.9602898564975363 };
  static const double kWeights[8] = { 0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                      0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                      0.2223810344533745, 0.1012285362903763 };
  const int pieces = 16;
  *jf = 0.0;
  *cross = 0.0;
  for (int p = 0; p < pieces; ++p)
    for (int k = 0; k < 8; ++k)
    {
      const double u = (p + 0.5 * (1.0 + kNodes[k])) / pieces;
      const double w = 0.5 * kWeights[k] / pieces;
      const double fd = f(Jet<9>::variable(u)).derivative(n + 1);
      const double gd = g(Jet<9>::variable(u)).derivative(n + 1);
      *jf += w * fd * fd;
      *cross += w * fd * gd;
    }
}
}  // namespace

TEST(BlendingPolynomials, MinimiseTheEnergyJnAmongCompetitorsWithTheSameBoundaryConditions)
{
  // §3/§4: J_n(w + ε p) = J_n(w) + ε² J_n(p) for any p flat to order n at both ends, because
  // ∫ w^{(n+1)} p^{(n+1)} = 0. Competitors p = u^{n+1}(1 − u)^{n+1} q(u), q random cubics.
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int n = 1; n <= 7; ++n)
    for (int which = 0; which < 2; ++which)
    {
      const BlendingPolynomial w = which == 0 ? BlendingPolynomial::increasing(n) : BlendingPolynomial::decreasing(n);
      for (int trial = 0; trial < 4; ++trial)
      {
        const double q0 = g(rng), q1 = g(rng), q2 = g(rng), q3 = g(rng);
        auto bump = [&](const Jet<9>& u) {
          Jet<9> b(1.0);
          for (int k = 0; k <= n; ++k)
            b = b * u * (Jet<9>(1.0) - u);
          return b * (Jet<9>(q0) + u * (Jet<9>(q1) + u * (Jet<9>(q2) + u * Jet<9>(q3))));
        };
        // The competitor satisfies the same boundary conditions.
        for (double end : { 0.0, 1.0 })
        {
          const Jet<9> b = bump(Jet<9>::variable(end));
          for (int m = 0; m <= n; ++m)
            EXPECT_NEAR(b.derivative(m), 0.0, 1e-9);
        }
        double jw, cross, jp, unused;
        energy(n, w, bump, &jw, &cross);
        energy(n, bump, bump, &jp, &unused);
        EXPECT_LT(std::abs(cross), 1e-9 * std::sqrt(jw * jp)) << "n=" << n;
        for (double c : { 0.5, -0.5, 1e-2, -1e-2, 1e-4, -1e-4 })
        {
          const double eps = c * std::sqrt(jw / jp);  // J_n(w + ε p) − J_n(w) = c² J_n(w)
          auto competitor = [&](const Jet<9>& u) { return w(u) + Jet<9>(eps) * bump(u); };
          double jc, unused2;
          energy(n, competitor, competitor, &jc, &unused2);
          EXPECT_GT(jc, jw) << "n=" << n << " eps=" << eps;
          EXPECT_NEAR(jc - jw, eps * eps * jp, 1e-11 * jw);
        }
      }
    }
}

TEST(BlendingPolynomials, RejectOrderZero)
{
  EXPECT_THROW(BlendingPolynomial::increasing(0), InvalidInputError);
  EXPECT_THROW(BlendingPolynomial::decreasing(kMaxBlendingContinuity + 1), InvalidInputError);
  EXPECT_THROW(BlendedSpline<Euclidean>({ Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0) }, { 0.0, 1.0 }, 0),
               InvalidInputError);
}

// ---- Blended splines in every geometry ----------------------------------------------------

TYPED_TEST(BlendedTest, PassesThroughEveryWaypointAtItsTime)
{
  using G = typename TypeParam::G;
  std::mt19937 rng(31);
  for (std::size_t n : { 2, 3, 4, 7 })
    for (int continuity : { 1, 2, 5 })
    {
      const auto x = TypeParam::points(rng, n);
      const auto t = randomTimes(rng, n);
      const BlendedSpline<G> c(x, t, continuity);
      for (std::size_t i = 0; i < n; ++i)
      {
        EXPECT_LT(TypeParam::distance(c.template evaluate<double>(t[i], Side::kLeft), x[i]), 1e-12) << i;
        EXPECT_LT(TypeParam::distance(c.template evaluate<double>(t[i], Side::kRight), x[i]), 1e-12) << i;
      }
    }
}

TYPED_TEST(BlendedTest, IsCnButNotCnPlusOneAtTheWaypoints)
{
  std::mt19937 rng(32);
  for (int trial = 0; trial < 3; ++trial)
  {
    checkContinuity<TypeParam, 1>(rng, 7);
    checkContinuity<TypeParam, 2>(rng, 7);
    checkContinuity<TypeParam, 3>(rng, 7);
    checkContinuity<TypeParam, 4>(rng, 7);
  }
}

TYPED_TEST(BlendedTest, HighContinuityUpToEight)
{
  std::mt19937 rng(33);
  checkContinuity<TypeParam, 6>(rng, 6);
  checkContinuity<TypeParam, 8>(rng, 6);
}

TYPED_TEST(BlendedTest, LocalityMovingOneWaypointChangesAtMostFourSegments)
{
  using G = typename TypeParam::G;
  std::mt19937 rng(34);
  const std::size_t n = 10;
  for (std::size_t j : { 0, 1, 2, 5, 8, 9 })
  {
    const auto x = TypeParam::points(rng, n);
    const auto t = randomTimes(rng, n);
    auto moved = x;
    const auto other = TypeParam::points(rng, 2);
    moved[j] = geodesic<G>(x[j], other[1], 0.1);  // a nearby point
    const BlendedSpline<G> a(x, t, 3), b(moved, t, 3);
    std::vector<bool> changed(n - 1, false);
    for (std::size_t i = 0; i + 1 < n; ++i)
      for (int s = 0; s <= 20; ++s)
      {
        const double ts = t[i] + (t[i + 1] - t[i]) * s / 20.0;
        const auto pa = flatten(a.template evaluate<Jet<2>>(Jet<2>::variable(ts), Side::kRight));
        const auto pb = flatten(b.template evaluate<Jet<2>>(Jet<2>::variable(ts), Side::kRight));
        if (s < 20 && pa != pb)
          changed[i] = true;
      }
    // Segment i = [t_i, t_{i+1}] may change only for j − 2 ≤ i ≤ j + 1 (bit-identical elsewhere),
    // and does change there: the bound is attained.
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
      const bool inside = i + 2 >= j && i <= j + 1;
      EXPECT_EQ(changed[i], inside) << "moved waypoint " << j << ", segment " << i;
    }
  }
}

TYPED_TEST(BlendedTest, CurveInterfaceMatchesEvaluate)
{
  using G = typename TypeParam::G;
  std::mt19937 rng(35);
  const auto x = TypeParam::points(rng, 5);
  const auto t = randomTimes(rng, 5);
  const BlendedSpline<G> c(x, t, 2);
  const Curve<G>& base = c;
  EXPECT_EQ(base.breakpoints(), t);
  EXPECT_EQ(base.startTime(), t.front());
  EXPECT_EQ(base.endTime(), t.back());
  EXPECT_EQ(base.controlPoints().size(), x.size());
  for (double s : { 0.1, 0.45, 0.8 })
  {
    const double ts = t.front() + s * (t.back() - t.front());
    EXPECT_LT(TypeParam::distance(base.value(ts), c.template evaluate<double>(ts, Side::kRight)), 1e-15);
  }
}

TEST(Blended, EuclideanEqualsTheClassicalFormula)
{
  // In R^n the three-point curves are Lagrange parabolas and eq. 5.1 in the translation group is
  // q(t) = L_i(τ_1) − x_i + L_{i−1}(τ_2), τ_j = t_i + h w_{j,n}(u); ends are L_0 and L_{N−3}.
  std::mt19937 rng(36);
  for (int n : { 1, 2, 3, 4 })
  {
    const std::size_t num = 7;
    const auto x = EuclideanConfig::points(rng, num);
    const auto t = randomTimes(rng, num);
    const BlendedSpline<Euclidean> c(x, t, n);
    auto lagrange = [&](std::size_t k, double s) {  // through x_k, x_{k+1}, x_{k+2}
      Eigen::VectorXd r = Eigen::VectorXd::Zero(3);
      for (std::size_t a = 0; a < 3; ++a)
      {
        double l = 1.0;
        for (std::size_t b = 0; b < 3; ++b)
          if (b != a)
            l *= (s - t[k + b]) / (t[k + a] - t[k + b]);
        r += l * x[k + a];
      }
      return r;
    };
    for (std::size_t i = 0; i + 1 < num; ++i)
      for (double s : { 0.0, 0.13, 0.5, 0.77, 0.999 })
      {
        const double ts = t[i] + s * (t[i + 1] - t[i]);
        Eigen::VectorXd expected;
        if (i == 0)
          expected = lagrange(0, ts);
        else if (i == num - 2)
          expected = lagrange(num - 3, ts);
        else
        {
          const double h = t[i + 1] - t[i];
          const double tau1 = t[i] + h * testW1(n, s);
          const double tau2 = t[i] + h * testW2(n, s);
          expected = lagrange(i, tau1) - x[i] + lagrange(i - 1, tau2);
        }
        EXPECT_LT((c.value(ts) - expected).norm(), 1e-12 * (1.0 + expected.norm())) << n << " " << i << " " << s;
      }
  }
}

TEST(Blended, RotationsAboutOneAxisAndTranslationsAreClassical)
{
  // For rotations about one fixed axis the curve is the classical one in the angle; for
  // the double-geodesic metric the translation is the Euclidean blended spline of the positions.
  std::mt19937 rng(37);
  const Eigen::Vector3d axis = test::randomUnitVector<3>(rng);
  const std::vector<double> angles{ 0.2, 1.1, 0.6, 1.9, 2.4, 1.5 };
  const std::vector<double> t{ 0.0, 0.7, 1.5, 3.0, 3.4, 4.6 };
  std::vector<Quaternion<double>> q;
  std::vector<Pose<double>> poses;
  std::vector<Eigen::VectorXd> a1, positions;
  std::normal_distribution<double> g(0.0, 1.0);
  for (double a : angles)
  {
    q.push_back(so3Exp<double>(a * axis));
    const Eigen::Vector3d p(g(rng), g(rng), g(rng));
    poses.emplace_back(q.back(), p);
    a1.push_back(Eigen::VectorXd::Constant(1, a));
    positions.push_back(p);
  }
  for (int n : { 1, 3 })
  {
    const BlendedSpline<So3> rot(q, t, n);
    const BlendedSpline<DoubleGeodesicSe3> dg(poses, t, n);
    const BlendedSpline<ScrewSe3> screw_rot(
        [&] {
          std::vector<Pose<double>> r;
          for (const auto& qq : q)
            r.emplace_back(qq, Eigen::Vector3d::Zero());
          return r;
        }(),
        t, n);
    const BlendedSpline<Euclidean> ang(a1, t, n), pos(positions, t, n);
    for (double s = t.front(); s <= t.back(); s += 0.0731)
    {
      const Quaternion<double> expected = so3Exp<double>(ang.value(s)[0] * axis);
      EXPECT_LT(So3Config::distance(rot.value(s), expected), 1e-13);
      EXPECT_LT(So3Config::distance(dg.value(s).q, expected), 1e-13);
      EXPECT_LT(test::poseDistance(screw_rot.value(s), Pose<double>(expected, Eigen::Vector3d::Zero())), 1e-13);
      EXPECT_LT((dg.value(s).p - pos.value(s)).norm(), 1e-13);
    }
  }
}

TEST(Blended, InvariantOnSe3AndRotationEquivariantOnSpheres)
{
  std::mt19937 rng(38);
  const std::vector<double> t{ 0.0, 1.0, 1.6, 2.9, 3.5, 5.0 };
  const auto x = test::randomPolygon(rng, t.size());
  const Pose<double> h = test::randomPose(rng);
  std::vector<Pose<double>> hx;
  for (const auto& p : x)
    hx.push_back(h * p);
  const BlendedSpline<ScrewSe3> s1(x, t, 2), s2(hx, t, 2);
  const BlendedSpline<DoubleGeodesicSe3> d1(x, t, 2), d2(hx, t, 2);
  std::vector<Pose<double>> xh;
  for (const auto& p : x)
    xh.push_back(p * h);
  const BlendedSpline<ScrewSe3> s3(xh, t, 2);  // the screw metric is bi-invariant
  for (double s = 0.0; s <= 5.0; s += 0.37)
  {
    EXPECT_LT(test::poseDistance(h * s1.value(s), s2.value(s)), 1e-12);
    EXPECT_LT(test::poseDistance(h * d1.value(s), d2.value(s)), 1e-12);
    EXPECT_LT(test::poseDistance(s1.value(s) * h, s3.value(s)), 1e-12);
  }

  const int dim = 5;
  const auto y = randomSpherePath(rng, t.size(), dim);
  Eigen::MatrixXd m(dim, dim);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int i = 0; i < dim * dim; ++i)
    m.data()[i] = g(rng);
  const Eigen::MatrixXd rotation = Eigen::HouseholderQR<Eigen::MatrixXd>(m).householderQ();  // orthogonal
  std::vector<Eigen::VectorXd> ry;
  for (const auto& p : y)
    ry.push_back(rotation * p);
  const BlendedSpline<Sphere> c1(y, t, 3), c2(ry, t, 3);
  for (double s = 0.0; s <= 5.0; s += 0.37)
    EXPECT_LT((rotation * c1.value(s) - c2.value(s)).norm(), 1e-12);
}

namespace
{
/// Rotation about the unit axis n by angle a (Rodrigues, via Eigen::AngleAxis).
Eigen::Vector3d rotateAbout(const Eigen::Vector3d& n, double a, const Eigen::Vector3d& p)
{
  return Eigen::AngleAxisd(a, n) * p;
}

/// Test-side circle through p0, p1, p2 on S²: axis n with the points counter-clockwise about it.
struct TestCircle
{
  Eigen::Vector3d axis;
  /// Angle about the axis from p to q, in (0, 2π).
  double angle(const Eigen::Vector3d& p, const Eigen::Vector3d& q) const
  {
    const Eigen::Vector3d rp = p - p.dot(axis) * axis, rq = q - q.dot(axis) * axis;
    double a = std::atan2(axis.dot(rp.cross(rq)), rp.dot(rq));
    return a <= 0.0 ? a + 2.0 * kPi : a;
  }
};
TestCircle circleThrough(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2)
{
  return TestCircle{ (p1 - p0).cross(p2 - p1).normalized() };
}
}  // namespace

TEST(Blended, ReproducesPobegailosCircleSplinesOnS2WithHisKnotRule)
{
  // §7: segment i is q_i(u) = R(n_i, w_1(u) φ_{i,1}) R(n_{i−1}, w_2(u) φ_{i,2}) p_i, where n_k is the
  // axis of the circle through p_k, p_{k+1}, p_{k+2}, φ_{i,1} the angle from p_i to p_{i+1} on
  // circle i and φ_{i,2} on circle i − 1; the first and last segments are circle arcs; the
  // knots are t_0 = 0, t_1 = φ_{0,1}, t_{i+1} = t_i + (φ_{i,2}/φ_{i−1,1})(t_i − t_{i−1}).
  std::mt19937 rng(39);
  for (int trial = 0; trial < 5; ++trial)
  {
    const auto pts = randomSpherePath(rng, 7, 3);
    std::vector<Eigen::Vector3d> p;
    for (const auto& v : pts)
      p.emplace_back(v);
    const std::size_t k = p.size();
    std::vector<TestCircle> circle;
    for (std::size_t j = 0; j + 2 < k; ++j)
      circle.push_back(circleThrough(p[j], p[j + 1], p[j + 2]));
    auto phi1 = [&](std::size_t i) { return circle[i].angle(p[i], p[i + 1]); };      // on circle i
    auto phi2 = [&](std::size_t i) { return circle[i - 1].angle(p[i], p[i + 1]); };  // on circle i − 1
    std::vector<double> t{ 0.0, phi1(0) };
    for (std::size_t i = 1; i + 1 < k; ++i)
      t.push_back(t[i] + phi2(i) / phi1(i - 1) * (t[i] - t[i - 1]));
    for (int n : { 1, 2, 3 })
    {
      const BlendedSpline<Sphere> c(pts, t, n);
      for (std::size_t i = 0; i + 1 < k; ++i)
        for (double u : { 0.0, 0.1, 0.35, 0.5, 0.8, 0.97 })
        {
          Eigen::Vector3d expected;
          if (i == 0)
            expected = rotateAbout(circle[0].axis, u * phi1(0), p[0]);
          else if (i == k - 2)
            expected = rotateAbout(circle[k - 3].axis, u * phi2(k - 2), p[k - 2]);
          else
            expected = rotateAbout(circle[i].axis, testW1(n, u) * phi1(i),
                                   rotateAbout(circle[i - 1].axis, testW2(n, u) * phi2(i), p[i]));
          const Eigen::VectorXd got = c.value(t[i] + u * (t[i + 1] - t[i]));
          EXPECT_LT((got - Eigen::VectorXd(expected)).norm(), 1e-12) << "n=" << n << " segment " << i << " u=" << u;
        }
    }
  }
}

TEST(Blended, SphereThreePointCurvesAreTheCirclesThroughTheirPoints)
{
  // On S^4 with arbitrary times: C_k passes its three points at their times and stays on their
  // circumcircle (test side: the circumcentre from the 2×2 Gram system in the points' plane).
  std::mt19937 rng(40);
  for (int trial = 0; trial < 20; ++trial)
  {
    const auto x = randomSpherePath(rng, 3, 5);
    const auto t = randomTimes(rng, 3);
    const Eigen::VectorXd a = x[0] - x[2], b = x[1] - x[2];
    Eigen::Matrix2d gram;
    gram << a.dot(a), a.dot(b), a.dot(b), b.dot(b);
    const Eigen::Vector2d st = gram.inverse() * Eigen::Vector2d(a.dot(a) / 2, b.dot(b) / 2);
    const Eigen::VectorXd centre = x[2] + st[0] * a + st[1] * b;
    const double radius = (x[0] - centre).norm();
    Eigen::MatrixXd plane(5, 2);
    plane << a, b;
    const BlendedSpline<Sphere> spline(x, t, 2);
    const ThreePointCurve<Sphere>& c = spline.threePointCurve(0);
    for (int i = 0; i < 3; ++i)
      EXPECT_LT((c.at(t[i]) - x[i]).norm(), 1e-13);
    for (double s = t[0] - 0.3; s <= t[2] + 0.3; s += 0.05)
    {
      const Eigen::VectorXd y = c.at(s);
      EXPECT_NEAR(y.norm(), 1.0, 1e-14);
      EXPECT_NEAR((y - centre).norm(), radius, 1e-12);
      const Eigen::VectorXd r = y - centre;
      const Eigen::VectorXd in_plane = plane * plane.colPivHouseholderQr().solve(r);
      EXPECT_LT((r - in_plane).norm(), 1e-12);
    }
    // The curve runs p_0 → p_1 → p_2: the angle is monotone for times proportional to the arcs.
    EXPECT_LT(c.angleAtFirst(), 0.0);
    EXPECT_GT(c.angleAtLast(), 0.0);
    EXPECT_LT(c.angleAtLast() - c.angleAtFirst(), 2.0 * kPi);
  }
}

TEST(Blended, DwellsAreAllowedOnEveryGeometry)
{
  // Two equal consecutive waypoints at different times: still interpolating and C^n (on the
  // sphere the circle degenerates to the great circle through the distinct points).
  std::mt19937 rng(41);
  auto x = randomSpherePath(rng, 6, 3);
  x[3] = x[2];
  const std::vector<double> t{ 0.0, 1.0, 2.0, 3.0, 4.5, 5.0 };
  const BlendedSpline<Sphere> c(x, t, 2);
  for (std::size_t i = 0; i < x.size(); ++i)
    EXPECT_LT((c.value(t[i]) - x[i]).norm(), 1e-13);
  for (std::size_t i = 1; i + 1 < x.size(); ++i)
  {
    const auto l = flatten(c.evaluate<Jet<3>>(Jet<3>::variable(t[i]), Side::kLeft));
    const auto r = flatten(c.evaluate<Jet<3>>(Jet<3>::variable(t[i]), Side::kRight));
    for (int k = 0; k <= 2; ++k)
    {
      double diff, scale;
      compareOrder(l, r, 0, k, &diff, &scale);
      EXPECT_LE(diff, 1e-9 * scale) << i << " " << k;
    }
  }
  for (double s = 0.0; s <= 5.0; s += 0.01)
    EXPECT_NEAR(c.value(s).norm(), 1.0, 1e-14);

  auto poses = test::randomPolygon(rng, 5);
  poses[2] = poses[1];
  const BlendedSpline<ScrewSe3> p(poses, { 0.0, 1.0, 2.0, 3.0, 4.0 }, 3);
  for (std::size_t i = 0; i < poses.size(); ++i)
    EXPECT_LT(test::poseDistance(p.value(static_cast<double>(i)), poses[i]), 1e-12);
}

TEST(Blended, AntipodalConsecutiveWaypointsAreNamed)
{
  std::vector<Eigen::VectorXd> x{ Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, -1, 0),
                                  Eigen::Vector3d(0, 0, 1) };
  try
  {
    BlendedSpline<Sphere>(x, { 0.0, 1.0, 2.0, 3.0 }, 2);
    FAIL() << "expected NonUniqueGeodesicError";
  }
  catch (const NonUniqueGeodesicError& e)
  {
    EXPECT_NE(std::string(e.what()).find("waypoints[1] and waypoints[2]"), std::string::npos) << e.what();
  }
  std::vector<Pose<double>> poses(3);
  poses[2].q = Quaternion<double>(0.0, 1.0, 0.0, 0.0);  // π about x from poses[1]
  EXPECT_THROW(BlendedSpline<ScrewSe3>(poses, { 0.0, 1.0, 2.0 }, 2), NonUniqueGeodesicError);
}

TEST(Blended, PlannerBuildsTheBlendedCurveWithTheRequestedContinuity)
{
  std::mt19937 rng(42);
  TrajectoryRequest request;
  request.waypoints = test::randomPolygon(rng, 6);
  request.times = { 0.0, 0.8, 1.5, 2.7, 3.1, 4.0 };
  request.curve = "blended";
  request.geometry = "screw";
  request.continuity = 3;
  request.sample_times = request.times;
  const TrajectoryResult result = generate(request, test::unhurriedLimits());
  ASSERT_EQ(result.samples.size(), request.times.size());
  for (std::size_t i = 0; i < request.times.size(); ++i)
    EXPECT_LT(test::poseDistance(result.samples[i].pose, request.waypoints[i]), 1e-12);
  const ValidatedRequest validated = validateRequest(request, PlannerLimits());
  const auto curve = makeCurve<ScrewSe3>(validated, request.times);
  const auto* blended = dynamic_cast<const BlendedSpline<ScrewSe3>*>(curve.get());
  ASSERT_NE(blended, nullptr);
  EXPECT_EQ(blended->continuity(), 3);
  request.continuity = 0;  // default 2
  const auto by_default = makeCurve<ScrewSe3>(validateRequest(request, PlannerLimits()), request.times);
  EXPECT_EQ(dynamic_cast<const BlendedSpline<ScrewSe3>&>(*by_default).continuity(), 2);
}

// Evaluating a blended spline (value and second-order jet) allocates nothing, at every
// continuity, in the SE(3) geometries (whose points are fixed-size); the blending polynomials'
// powers live on the stack.
TEST(Blended, EvaluationAllocatesNothing)
{
  std::mt19937 rng(41);
  std::vector<Pose<double>> x;
  for (int i = 0; i < 6; ++i)
    x.push_back(test::randomPose(rng));
  const std::vector<double> t{ 0.0, 0.4, 1.5, 1.9, 3.0, 3.2 };
  for (int n = 1; n <= kMaxBlendingContinuity; ++n)
  {
    const BlendedSpline<DoubleGeodesicSe3> dg(x, t, n);
    const BlendedSpline<ScrewSe3> screw(x, t, n);
    double sink = 0.0;
    const long before = test::allocationCount().load();
    for (double s = 0.0; s <= 3.2; s += 0.05)
    {
      sink += dg.value(s).p.x() + screw.value(s).p.y();
      sink += dg.jet(Jet<2>::variable(s), Side::kRight).p.z().coefficient(2) + screw.jet(Jet<2>::variable(s), Side::kRight).q.w().coefficient(1);
    }
    EXPECT_EQ(test::allocationCount().load() - before, 0) << "continuity " << n;
    EXPECT_TRUE(std::isfinite(sink));
  }
}
