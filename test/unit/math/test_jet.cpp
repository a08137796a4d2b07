// Taylor arithmetic against closed-form derivatives of test functions.
#include <gtest/gtest.h>

#include <cmath>

#include "se3_interpolation/math/jet.h"

using se3_interpolation::Jet;

namespace
{
/// Checks the first four derivatives of f at t against the given values.
template <class F>
void expectDerivatives(const F& f, double t, const std::array<double, 5>& expected, double tol)
{
  const Jet<4> y = f(Jet<4>::variable(t));
  for (int k = 0; k <= 4; ++k)
    EXPECT_NEAR(y.derivative(k), expected[k], tol * std::max(1.0, std::abs(expected[k]))) << "order " << k;
}
}  // namespace

TEST(Jet, Polynomial)
{
  // f = 3t³ − 2t + 1 at t = 1.5
  const double t = 1.5;
  expectDerivatives([](const Jet<4>& x) { return Jet<4>(3.0) * x * x * x - Jet<4>(2.0) * x + Jet<4>(1.0); }, t,
                    { 3 * t * t * t - 2 * t + 1, 9 * t * t - 2, 18 * t, 18, 0 }, 1e-14);
}

TEST(Jet, SinCos)
{
  const double t = 0.7;
  const double s = std::sin(2 * t), c = std::cos(2 * t);
  expectDerivatives([](const Jet<4>& x) { return sin(Jet<4>(2.0) * x); }, t, { s, 2 * c, -4 * s, -8 * c, 16 * s },
                    1e-14);
  expectDerivatives([](const Jet<4>& x) { return cos(Jet<4>(2.0) * x); }, t, { c, -2 * s, -4 * c, 8 * s, 16 * c },
                    1e-14);
}

TEST(Jet, SqrtAndDivision)
{
  const double t = 2.0;
  // sqrt(t): t^{1/2}, ½ t^{−1/2}, −¼ t^{−3/2}, ⅜ t^{−5/2}, −15/16 t^{−7/2}
  expectDerivatives([](const Jet<4>& x) { return sqrt(x); }, t,
                    { std::sqrt(t), 0.5 / std::sqrt(t), -0.25 * std::pow(t, -1.5), 0.375 * std::pow(t, -2.5),
                      -15.0 / 16.0 * std::pow(t, -3.5) },
                    1e-14);
  // 1/t: t⁻¹, −t⁻², 2t⁻³, −6t⁻⁴, 24t⁻⁵
  expectDerivatives([](const Jet<4>& x) { return Jet<4>(1.0) / x; }, t,
                    { 1 / t, -1 / (t * t), 2 / (t * t * t), -6 / std::pow(t, 4), 24 / std::pow(t, 5) }, 1e-14);
}

TEST(Jet, Atan2)
{
  // atan2(t, 1) = atan t: derivatives 1/(1+t²), −2t/(1+t²)², (6t² − 2)/(1+t²)³, 24t(1 − t²)/(1+t²)⁴
  const double t = 0.3;
  const double u = 1 + t * t;
  expectDerivatives([](const Jet<4>& x) { return atan2(x, Jet<4>(1.0)); }, t,
                    { std::atan(t), 1 / u, -2 * t / (u * u), (6 * t * t - 2) / (u * u * u),
                      24 * t * (1 - t * t) / std::pow(u, 4) },
                    1e-13);
  // atan2(sin t, cos t) = t on (−π, π), also in the second and third quadrants.
  for (double t0 : { 2.5, -2.5, 3.1 })
    expectDerivatives([](const Jet<4>& x) { return atan2(sin(x), cos(x)); }, t0, { t0, 1, 0, 0, 0 }, 1e-13);
}

TEST(Jet, ComparisonsUseTheValue)
{
  Jet<2> a = Jet<2>::variable(1.0);
  Jet<2> b(2.0);
  EXPECT_TRUE(a < b);
  EXPECT_FALSE(a > b);
  EXPECT_EQ(se3_interpolation::valueOf(a), 1.0);
}
