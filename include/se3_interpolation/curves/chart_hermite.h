// Two-point Hermite interpolation in the chart of a geometry G at a point x: the polynomial
//   P(τ) = Σ_{k=0}^{2m+1} c_k τ^k ∈ T_x,     c(τ) = G::exp(x, P(τ)),                          (H1)
// of odd degree 2m + 1 (m = 0, 1, 2) with the m + 1 Taylor coefficients (c_0, …, c_m) at τ = 0
// and (E_0, …, E_m) at τ = h, both jets of the chart G::log(x, ·) of the motions to be joined:
//   m = 0 (line):     c_1 h = A,                                      A = E_0 − c_0,
//   m = 1 (cubic):    c_2 h² = 3A − B,  c_3 h³ = −2A + B,             A = E_0 − c_0 − c_1 h,
//                                                                     B = (E_1 − c_1) h,
//   m = 2 (quintic):  c_3 h³ = 10A − 4B + C,  c_4 h⁴ = −15A + 7B − 2C,  c_5 h⁵ = 6A − 3B + C,
//                     A = E_0 − c_0 − c_1 h − c_2 h²,  B = (E_1 − c_1 − 2 c_2 h) h,  C = (E_2 − c_2) h²
// (the classical Hermite bases of degree 1, 3, 5, written in the monomials: the conditions
// P^(j)(h)/j! = E_j, j ≤ m, solved for the top m + 1 coefficients). G::exp(x, ·) inverts
// G::log(x, ·) as a map, hence on jets too, so c has at 0 and h the values, velocities and (m = 2)
// accelerations of the motions whose chart jets were given: joined motions are C^m there (in any
// geometry whose log at x is smooth near both ends: rotations below π from x). In the abelian cases
// (R^n, pure translations, rotations about one axis) the chart is linear and (H1) is the classical
// Hermite polynomial.
//
// Used by the joining segment of replanning (start_join.h) and by the goal trajectories of the
// action server (execution/goal_trajectory.h), one segment per pair of consecutive points.
#pragma once

#include <array>
#include <cstddef>

#include "se3_interpolation/geometry/geometry.h"
#include "se3_interpolation/math/jet.h"

namespace se3_interpolation
{
/// Highest degree of (H1): the quintic.
constexpr int kMaxChartHermiteDegree = 5;

/// The coefficients c_0 … c_5 of (H1) (unused ones zero).
template <class G>
using ChartPolynomial = std::array<typename G::template Tangent<double>, kMaxChartHermiteDegree + 1>;

namespace detail
{
/// The coefficients 0, 1, 2 of a tangent of jets, as three tangents of doubles.
template <class G>
std::array<typename G::template Tangent<double>, 3> tangentCoefficients(const typename G::template Tangent<Jet<2>>& v)
{
  std::array<typename G::template Tangent<double>, 3> c;
  for (int k = 0; k < 3; ++k)
  {
    c[k].resize(v.size());
    for (Eigen::Index i = 0; i < v.size(); ++i)
      c[k][i] = v[i].coefficient(k);
  }
  return c;
}
}  // namespace detail

/// The second-order jet of a pose moving with the given velocity and acceleration (planner.h
/// conventions: ṗ, p̈ and the spatial ω, ω̇ with Ṙ = [ω]× R). The inverse of kinematicsFromJet:
/// q̇ = ½ (0, ω) q and q̈ = ½ (0, ω̇) q + ¼ (0, ω)(0, ω) q; a jet stores q̈/2.
inline Pose<Jet<2>> poseJet(const Pose<double>& x, const Twist& velocity, const Twist& acceleration)
{
  const Quaternion<double> w(0.0, velocity.angular.x(), velocity.angular.y(), velocity.angular.z());
  const Quaternion<double> dw(0.0, acceleration.angular.x(), acceleration.angular.y(), acceleration.angular.z());
  const Quaternion<double> q1 = Quaternion<double>(w.coeffs() * 0.5) * x.q;
  const Quaternion<double> q2a = dw * x.q;
  const Quaternion<double> q2b = w * (w * x.q);
  const Eigen::Vector4d q2 = 0.25 * q2a.coeffs() + 0.125 * q2b.coeffs();  // q̈/2
  Pose<Jet<2>> j;
  Eigen::Matrix<Jet<2>, 4, 1> c;
  for (int i = 0; i < 4; ++i)
  {
    c[i] = Jet<2>(x.q.coeffs()[i]);
    c[i].coefficient(1) = q1.coeffs()[i];
    c[i].coefficient(2) = q2[i];
  }
  j.q.coeffs() = c;
  for (int i = 0; i < 3; ++i)
  {
    j.p[i] = Jet<2>(x.p[i]);
    j.p[i].coefficient(1) = velocity.linear[i];
    j.p[i].coefficient(2) = 0.5 * acceleration.linear[i];
  }
  return j;
}

/// The chart jet (c_0, c_1, c_2) of a motion at x: the Taylor coefficients at 0 of
/// τ ↦ G::log(x, X(τ)), X the motion's second-order jet (e.g. poseJet).
/// @throws NonUniqueGeodesicError when X(0) is half a turn from x
template <class G>
std::array<typename G::template Tangent<double>, 3> chartJet(const typename G::template Point<double>& x,
                                                             const typename G::template Point<Jet<2>>& motion)
{
  return detail::tangentCoefficients<G>(G::log(G::template cast<Jet<2>>(x), motion));
}

/// The coefficients of (H1) of degree 2m + 1 from the chart jets c (at τ = 0) and e (at τ = h),
/// of which the first m + 1 are read.
/// @param order m ∈ {0, 1, 2}: 0 joins the values (a geodesic), 1 also the velocities, 2 also the
///        accelerations
template <class G>
ChartPolynomial<G> chartHermite(const std::array<typename G::template Tangent<double>, 3>& c,
                                const std::array<typename G::template Tangent<double>, 3>& e, double h, int order)
{
  using Tangent = typename G::template Tangent<double>;
  ChartPolynomial<G> p;
  for (Tangent& x : p)
    x = Tangent::Zero(c[0].size());
  p[0] = c[0];
  if (order == 0)
  {
    p[1] = Tangent((e[0] - c[0]) / h);
    return p;
  }
  p[1] = c[1];
  const double h2 = h * h, h3 = h2 * h;
  if (order == 1)
  {
    const Tangent a = e[0] - c[0] - c[1] * h;
    const Tangent b = (e[1] - c[1]) * h;
    p[2] = Tangent((3.0 * a - b) / h2);
    p[3] = Tangent((-2.0 * a + b) / h3);
    return p;
  }
  p[2] = c[2];
  const Tangent a = e[0] - c[0] - c[1] * h - c[2] * h2;
  const Tangent b = (e[1] - c[1] - c[2] * (2.0 * h)) * h;
  const Tangent cc = (e[2] - c[2]) * h2;
  p[3] = Tangent((10.0 * a - 4.0 * b + cc) / h3);
  p[4] = Tangent((-15.0 * a + 7.0 * b - 2.0 * cc) / (h3 * h));
  p[5] = Tangent((6.0 * a - 3.0 * b + cc) / (h3 * h2));
  return p;
}

/// Whether every coefficient of (H1) is finite (a segment too short for its data overflows).
template <class G>
bool finiteCoefficients(const ChartPolynomial<G>& p)
{
  for (const auto& c : p)
    if (!c.allFinite())
      return false;
  return true;
}

/// (H1) at τ (a double or a jet of time): G::exp(x, P(τ)), P of degree `degree` by Horner's rule.
template <class G, class S>
typename G::template Point<S> chartPolynomialAt(const typename G::template Point<double>& x,
                                                const ChartPolynomial<G>& p, int degree, const S& tau)
{
  using TangentS = typename G::template Tangent<S>;
  TangentS v = p[static_cast<std::size_t>(degree)].template cast<S>();
  for (int k = degree - 1; k >= 0; --k)
    v = TangentS(v * tau + p[static_cast<std::size_t>(k)].template cast<S>());
  return G::exp(G::template cast<S>(x), v);
}

}  // namespace se3_interpolation
