// Quadrature and one-dimensional maximisation for the integral figures (analysis/figures.h)
// and the timing checks.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

namespace se3_interpolation
{
/// 8-point Gauss–Legendre nodes and weights on [−1, 1] (exact for polynomials of degree 15;
/// Abramowitz & Stegun, table 25.4).
constexpr std::array<double, 8> kGaussNodes = { -0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                                -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                                0.7966664774136267,  0.9602898564975363 };
constexpr std::array<double, 8> kGaussWeights = { 0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                                  0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                                  0.2223810344533745, 0.1012285362903763 };

/// 4-point Gauss–Legendre nodes and weights on [−1, 1] (exact for polynomials of degree 7;
/// Abramowitz & Stegun, table 25.4): the chord length of the constant-speed timing's short intervals.
constexpr std::array<double, 4> kGauss4Nodes = { -0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                                 0.8611363115940526 };
constexpr std::array<double, 4> kGauss4Weights = { 0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                                   0.3478548451374538 };

/// Golden-section iterations at most: each shrinks the bracket by 0.618, so 60 reach 1e-13 of
/// any bracket the figures start from.
constexpr int kGoldenMaxIterations = 60;
/// The search stops when the bracket is below this fraction of (1 + |a|): a few ulps above
/// double rounding of the times.
constexpr double kGoldenRelativeWidth = 1e-13;

/// Maximises f on [a, b] around an initial best point by golden-section search.
inline double goldenMax(const std::function<double(double)>& f, double a, double b, double best)
{
  const double r = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = b - r * (b - a);
  double x2 = a + r * (b - a);
  double f1 = f(x1);
  double f2 = f(x2);
  for (int i = 0; i < kGoldenMaxIterations && b - a > kGoldenRelativeWidth * (1.0 + std::abs(a)); ++i)
  {
    if (f1 > f2)
    {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - r * (b - a);
      f1 = f(x1);
    }
    else
    {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + r * (b - a);
      f2 = f(x2);
    }
  }
  return std::max({ best, f1, f2 });
}
}  // namespace se3_interpolation
