// math/quadrature.h: the 8-point Gauss–Legendre rule integrates every polynomial of degree ≤ 15
// exactly (and x^16 not: the rule is the one claimed), and golden-section search finds interior
// maxima to the bracket's resolution.
#include <gtest/gtest.h>

#include <cmath>

#include "se3_interpolation/math/quadrature.h"

using namespace se3_interpolation;

namespace
{
/// ∫_{-1}^{1} x^k dx by the rule.
double gaussMonomial(int k)
{
  double sum = 0.0;
  for (std::size_t i = 0; i < kGaussNodes.size(); ++i)
    sum += kGaussWeights[i] * std::pow(kGaussNodes[i], k);
  return sum;
}
}  // namespace

TEST(Quadrature, GaussLegendreIsExactToDegreeFifteen)
{
  for (int k = 0; k <= 15; ++k)
  {
    const double exact = k % 2 == 1 ? 0.0 : 2.0 / (k + 1);
    EXPECT_NEAR(gaussMonomial(k), exact, 1e-15) << "x^" << k;
  }
  // Degree 16 is beyond an 8-point rule: its error for f is 2^17 (8!)^4 / (17 (16!)^3) f^(16),
  // 4.65e-5 for x^16 (f^(16) = 16!).
  EXPECT_NEAR(2.0 / 17.0 - gaussMonomial(16), 4.654830926598375e-5, 1e-12);
  // Nodes symmetric, weights positive and summing to the length of [-1, 1].
  for (std::size_t i = 0; i < kGaussNodes.size(); ++i)
  {
    EXPECT_DOUBLE_EQ(kGaussNodes[i], -kGaussNodes[kGaussNodes.size() - 1 - i]);
    EXPECT_GT(kGaussWeights[i], 0.0);
  }
}

TEST(Quadrature, GoldenSectionFindsInteriorMaxima)
{
  // A parabola with its top at c: the maximum 3 to rounding, wherever c lies in the bracket.
  for (double c : { -0.7, 0.0, 0.123456789, 1.9 })
    EXPECT_NEAR(goldenMax([c](double x) { return 3.0 - (x - c) * (x - c); }, -1.0, 2.0, -1e300), 3.0, 1e-15) << c;
  // sin on [0, 3]: 1 at π/2 (quadratic near the top, so the value is exact to rounding).
  EXPECT_NEAR(goldenMax([](double x) { return std::sin(x); }, 0.0, 3.0, 0.0), 1.0, 1e-15);
  // The best value known before the search is kept when the search finds less.
  EXPECT_EQ(goldenMax([](double x) { return x; }, 0.0, 1.0, 5.0), 5.0);
}
