// math/lie_coefficients.h: the scalar coefficients of the closed forms of lie_groups.h (Exp, Log
// and the left Jacobian V of SO(3) and SE(3)) and their derivatives, each switching to its Taylor
// series in θ² where the direct formula cancels. Templates over the scalar (double or Jet<K>).
//
// V(ω) w = w + A ω × w + B ω × (ω × w) with A(θ) = (1 − cos θ)/θ², B(θ) = (θ − sin θ)/θ³
// (lie_groups.h's file comment); V(ω)⁻¹ has C(θ) = (1 − (θ/2) cot(θ/2))/θ² on [ω]×².
#pragma once

#include <cmath>
#include <cstddef>

#include "se3_interpolation/math/jet.h"

namespace se3_interpolation
{
/// Below this θ² the small-angle series are used (θ < 0.2 rad).
constexpr double kSeriesThetaSquared = 0.04;

namespace detail
{
template <class S, std::size_t N>
S horner(const S& x, const double (&c)[N])
{
  S r(c[N - 1]);
  for (std::size_t i = N - 1; i-- > 0;)
    r = r * x + S(c[i]);
  return r;
}

/// sin(θ/2)/θ and cos(θ/2) from θ².
template <class S>
void halfAngle(const S& theta2, S* sin_half_over_theta, S* cos_half)
{
  using std::sqrt;
  if (valueOf(theta2) < kSeriesThetaSquared)
  {
    static constexpr double ks[] = { 1.0 / 2,       -1.0 / 48,       1.0 / 3840,
                                     -1.0 / 645120, 1.0 / 185794560, -1.0 / 81749606400.0 };
    static constexpr double kc[] = { 1.0, -1.0 / 8, 1.0 / 384, -1.0 / 46080, 1.0 / 10321920, -1.0 / 3715891200.0 };
    *sin_half_over_theta = horner(theta2, ks);
    *cos_half = horner(theta2, kc);
    return;
  }
  const S theta = sqrt(theta2);
  S s, c;
  sincos(S(theta / 2.0), &s, &c);
  *sin_half_over_theta = s / theta;
  *cos_half = c;
}

/// B(θ) = (θ − sin θ)/θ³.
template <class S>
S screwB(const S& theta2)
{
  using std::sin;
  using std::sqrt;
  if (valueOf(theta2) < kSeriesThetaSquared)
  {
    static constexpr double k[] = { 1.0 / 6,        -1.0 / 120,          1.0 / 5040,           -1.0 / 362880,
                                    1.0 / 39916800, -1.0 / 6227020800.0, 1.0 / 1307674368000.0 };
    return horner(theta2, k);
  }
  const S theta = sqrt(theta2);
  return (theta - sin(theta)) / (theta2 * theta);
}

/// B(θ) from θ², k = sin(θ/2)/θ and c = cos(θ/2), reusing them: sin θ/θ = 2kc.
template <class S>
S screwB(const S& theta2, const S& k, const S& c)
{
  if (valueOf(theta2) < kSeriesThetaSquared)
    return screwB(theta2);
  return (S(1.0) - 2.0 * k * c) / theta2;
}

/// Below this θ² (θ < 1 rad) screwCoefficients sums its rates' series, where nine terms reach one ulp:
/// the quotients, used above it, lose up to 2e-14 relative just above θ = 1 (1e-13 at θ = 0.2).
constexpr double kRateSeriesThetaSquared = 1.0;

/// V(ω)'s coefficients at x = θ² and their derivatives with respect to x (screwCoefficients).
struct ScrewCoefficients
{
  double sin_half_over_theta = 0.0;  ///< sin(θ/2)/θ (halfAngle)
  double cos_half = 1.0;             ///< cos(θ/2)
  double a = 0.5;                    ///< A = (1 − cos θ)/θ² = 2 (sin(θ/2)/θ)²
  double b = 1.0 / 6;                ///< B = (θ − sin θ)/θ³ (screwB)
  double da = -1.0 / 24;             ///< dA/dx
  double db = -1.0 / 120;            ///< dB/dx
};

/// The coefficients of V(ω) w = w + A ω × w + B ω × (ω × w) at x = θ² with their x-derivatives:
/// dA/dx = (1 − B x − 2A)/(2x) and dB/dx = (A − 3B)/(2x) (from sin θ/θ = 1 − B x and
/// cos θ = 1 − A x), or below kRateSeriesThetaSquared their Taylor series
/// Σ_{k≥1} (−1)^k k x^(k−1)/(2k+2)! and Σ_{k≥1} (−1)^k k x^(k−1)/(2k+3)!.
inline ScrewCoefficients screwCoefficients(double x)
{
  ScrewCoefficients r;
  halfAngle(x, &r.sin_half_over_theta, &r.cos_half);
  r.a = 2.0 * r.sin_half_over_theta * r.sin_half_over_theta;
  r.b = screwB(x, r.sin_half_over_theta, r.cos_half);
  if (x < kRateSeriesThetaSquared)
  {
    static constexpr double ka[] = { -1.0 / 24,
                                     1.0 / 360,
                                     -1.0 / 13440,
                                     1.0 / 907200,
                                     -1.0 / 95800320.0,
                                     1.0 / 14529715200.0,
                                     -1.0 / 2988969984000.0,
                                     1.0 / 800296713216000.0,
                                     -1.0 / 270322445352960000.0 };
    static constexpr double kb[] = { -1.0 / 120,
                                     1.0 / 2520,
                                     -1.0 / 120960,
                                     1.0 / 9979200,
                                     -1.0 / 1245404160.0,
                                     1.0 / 217945728000.0,
                                     -1.0 / 50812489728000.0,
                                     1.0 / 15205637551104000.0,
                                     -1.0 / 5676771352412160000.0 };
    r.da = horner(x, ka);
    r.db = horner(x, kb);
    return r;
  }
  r.da = (1.0 - r.b * x - 2.0 * r.a) / (2.0 * x);
  r.db = (r.a - 3.0 * r.b) / (2.0 * x);
  return r;
}

/// Below this θ² (θ < 2 rad) screwSecondDerivatives sums its series, where eleven terms reach one
/// ulp: the quotients, used above it, divide by x once more than screwCoefficients' and lose up to
/// 3e-12 relative at θ² = 0.5 (2e-14 just above θ = 2).
constexpr double kSecondRateSeriesThetaSquared = 4.0;

/// The second x-derivatives of V(ω)'s coefficients A and B (screwCoefficients) at x = θ².
struct ScrewSecondDerivatives
{
  double dda = 1.0 / 360;   ///< d²A/dx²
  double ddb = 1.0 / 2520;  ///< d²B/dx²
};

/// d²A/dx² = −(x dB/dx + B + 4 dA/dx)/(2x) and d²B/dx² = (dA/dx − 5 dB/dx)/(2x) (screwCoefficients'
/// quotients differentiated once more), or below kSecondRateSeriesThetaSquared their Taylor series
/// Σ_{k≥2} (−1)^k k (k − 1) x^(k−2)/(2k+2)! and Σ_{k≥2} (−1)^k k (k − 1) x^(k−2)/(2k+3)!.
/// `c` holds the coefficients at the same x.
inline ScrewSecondDerivatives screwSecondDerivatives(double x, const ScrewCoefficients& c)
{
  ScrewSecondDerivatives r;
  if (x < kSecondRateSeriesThetaSquared)
  {
    static constexpr double ka[] = { 1.0 / 360.0,
                                     -1.0 / 6720.0,
                                     1.0 / 302400.0,
                                     -1.0 / 23950080.0,
                                     1.0 / 2905943040.0,
                                     -1.0 / 498161664000.0,
                                     1.0 / 114328101888000.0,
                                     -1.0 / 33790305669120000.0,
                                     1.0 / 12488896975306752000.0,
                                     -1.0 / 5640440015756722176000.0,
                                     1.0 / 3055238341868224512000000.0 };
    static constexpr double kb[] = { 1.0 / 2520.0,
                                     -1.0 / 60480.0,
                                     1.0 / 3326400.0,
                                     -1.0 / 311351040.0,
                                     1.0 / 43589145600.0,
                                     -1.0 / 8468748288000.0,
                                     1.0 / 2172233935872000.0,
                                     -1.0 / 709596419051520000.0,
                                     1.0 / 287244630432055296000.0,
                                     -1.0 / 141011000393918054400000.0,
                                     1.0 / 82491435230442061824000000.0 };
    r.dda = horner(x, ka);
    r.ddb = horner(x, kb);
    return r;
  }
  r.dda = -(x * c.db + c.b + 4.0 * c.da) / (2.0 * x);
  r.ddb = (c.da - 5.0 * c.db) / (2.0 * x);
  return r;
}

/// C(θ) = (1 − (θ/2) cot(θ/2))/θ², the coefficient of [ω]×² in V(ω)⁻¹.
template <class S>
S screwC(const S& theta2)
{
  using std::sqrt;
  if (valueOf(theta2) < kSeriesThetaSquared)
  {
    static constexpr double k[] = { 1.0 / 12,           1.0 / 720,      1.0 / 30240,
                                    1.0 / 1209600,      1.0 / 47900160, 691.0 / 1307674368000.0,
                                    1.0 / 74724249600.0 };
    return horner(theta2, k);
  }
  const S half = sqrt(theta2) / 2.0;
  S s, c;
  sincos(half, &s, &c);
  return (S(1.0) - half * c / s) / theta2;
}

/// 2 atan2(n, w)/n from n² (w ≥ 0 assumed): the factor taking a quaternion's
/// vector part to its rotation vector.
template <class S>
S logFactor(const S& n2, const S& w)
{
  using std::atan2;
  using std::sqrt;
  if (valueOf(n2) < 0.01)
  {
    // atan(x)/x = Σ (−1)^j x^{2j}/(2j+1), x = n/w, x² ≤ 0.0102.
    static constexpr double k[] = {
      1.0, -1.0 / 3, 1.0 / 5, -1.0 / 7, 1.0 / 9, -1.0 / 11, 1.0 / 13, -1.0 / 15, 1.0 / 17
    };
    return S(2.0) * horner(S(n2 / (w * w)), k) / w;
  }
  const S n = sqrt(n2);
  return S(2.0) * atan2(n, w) / n;
}
}  // namespace detail
}  // namespace se3_interpolation
