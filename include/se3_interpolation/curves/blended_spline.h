// Pobegailo's blending polynomials and C^n blended splines in any geometry of the core.
//
// After Pobegailo, "Construction of spline curves on smooth manifolds by action of Lie groups",
// with the errors of the printed text corrected as noted below.
//
// 1. Blending polynomials (§3, §4). For n ≥ 1, Bézier polynomials of degree 2n + 1 with the
//    control values c_j (j = 0 … 2n + 1), b_{d,j}(u) = C(d, j) (1 − u)^{d−j} u^j:
//      w_{1,n}(u) = Σ_{i=1}^{n+1} b_{2n+1,n+i}(u) (n+i)/(2n+1)     (eq. 3.1): c_j = j/(2n+1) for j > n, else 0
//      w_{2,n}(u) = Σ_{i=1}^{n}   b_{2n+1,i}(u)   i/(2n+1)         (eq. 4.1): c_j = j/(2n+1) for j ≤ n, else 0
//    Boundary values: w_1(0) = 0, w_1(1) = 1, w_1^{(m)}(0) = 0, w_1'(1) = 1, w_1^{(m)}(1) = 0 (m = 2 … n)
//    (eqs. 3.2–3.5); w_2(0) = w_2(1) = 0, w_2'(0) = 1, w_2^{(m)}(0) = 0 (m = 2 … n), w_2^{(m)}(1) = 0
//    (eqs. 4.2–4.5). Each minimises J_n(f) = ∫_0^1 |f^{(n+1)}(u)|² du under its own boundary
//    conditions. Since the control values of u itself are j/(2n+1), w_{1,n}(u) + w_{2,n}(u) = u.
//
// 2. Blending (§5–6, eqs. 5.1 and 6.4). Two curves through p with displacements g_1(u), g_2(u)
//    (g_j(0) = e) are blended by q(u) = g_1(w_{1,n}(u)) g_2(w_{2,n}(u)) p: q follows g_2 p to order
//    n at u = 0 and g_1 p to order n at u = 1, because g_1(w_1(u)) = e + O(u^{n+1}) and
//    g_2(w_2(u)) = e + O((1 − u)^{n+1}).
//
// 3. Splines (§7). For waypoints x_0 … x_{N−1} at times t_0 < … < t_{N−1}, let C_k be a curve
//    through x_k, x_{k+1}, x_{k+2} at their times (k = 0 … N − 3). On [t_i, t_{i+1}],
//    u = (t − t_i)/h_i, h_i = t_{i+1} − t_i, τ_j = t_i + h_i w_{j,n}(u):
//      segment 0:               C_0(t)
//      segment i (1 … N − 3):   the motion of C_i from x_i = C_i(t_i) to C_i(τ_1), applied to C_{i−1}(τ_2)
//      segment N − 2:           C_{N−3}(t)
//    (N = 2: the geodesic; N = 3: C_0 on the whole domain.) Both neighbours of t_{i+1} follow
//    C_i to order n there, so the spline is C^n at every waypoint with n = `continuity`, and
//    generally not C^{n+1}. The pieces are analytic.
//
// The three-point curves C_k and their motions, per geometry:
//  - Sphere S^m (Pobegailo's own example, §7 and Fig. 3): C_k is the circle through the three
//    points (the sphere cut by their affine plane), the orbit of the one-parameter subgroup
//    exp(θ J) of SO(m+1) that rotates the circle's plane about its centre. Its angle θ(t) is the
//    quadratic through the three points' angles at their times; the motion is exp((θ(τ) − θ(t_k)) J),
//    so segment i is exactly Pobegailo's exp(w_1 φ_{i,1} J_i) exp(w_2 φ_{i,2} J_{i−1}) x_i whenever
//    the times satisfy his knot rule (then θ is linear in t: the circles are traversed at constant
//    speed, as in the paper). For other times the quadratic angle keeps every circle on its three
//    points at their times, which is what C^n needs. If two of the three points coincide (a dwell)
//    the circle is not defined; the great circle through the distinct points is used instead, with
//    the same quadratic angle.
//  - Lie groups (ScrewSe3, DoubleGeodesicSe3 = SO(3) × R³, So3) and Euclidean R^n: no one-parameter
//    subgroup coset passes through three generic points, so C_k is the quadratic in the normal
//    coordinates centred at the middle point: C_k(t) = exp(x_{k+1}, ℓ_0(t) log(x_{k+1}, x_k)
//    + ℓ_2(t) log(x_{k+1}, x_{k+2})), ℓ_j the Lagrange basis of the three times. It is the Lagrange
//    parabola in R^n and the one-parameter subgroup itself when the three points lie on one at
//    proportional times (the analogue of the circle's constant speed); it is invariant under left
//    (and for the bi-invariant screw metric, right) translations; and it is smooth for all t (one
//    exponential, no logarithm of moving points). The motion is left multiplication by C_k(τ) x_k⁻¹,
//    so segment i is C_i(τ_1) ⋆ x_i⁻¹ ⋆ C_{i−1}(τ_2) = exp(C_i(τ_1), log(x_i, C_{i−1}(τ_2))) — eq. 5.1
//    in the group itself. In R^n: C_i(τ_1) − x_i + C_{i−1}(τ_2).
//
// Why Pobegailo's product rather than a pointwise geodesic blend exp(C_{i−1}, s(u) log(C_{i−1}, C_i)):
// it is the paper's construction (the polynomials w_{1,n}, w_{2,n} exist for it; the pointwise blend
// would need the "smoothstep" w_{1,n}(u) + w_{2,n}(1 − u) instead), and on S² it reproduces the
// paper's circle splines exactly.
//
// Locality: waypoint x_j enters C_{j−2}, C_{j−1}, C_j only, so moving it changes at most the four
// segments in [t_{j−2}, t_{j+2}] (fewer at the ends); the rest of the curve is bit-identical.
//
// Corrections to the paper's printed text (OCR or typesetting):
//  - §4: the printed w_{2,2}(u) = (1 − u)²u³ + 4(1 − u)u⁴ has w'(0) = 0; eq. 4.1 gives
//    w_{2,2}(u) = (1 − u)⁴u + 4(1 − u)³u². The derivation after eq. 4.3 is at u = 0, not u = 1.
//  - §5: "g_1(w_{2,n}(u)) and g_2(w_{1,n}(u))" should read g_1(w_{1,n}(u)) and g_2(w_{2,n}(u)), and
//    g(0) = g_1(0) g_2(0).
//  - §3 proof: |(g − w_{1,n})^{(n)}|² should be the (n + 1)-th derivative.
//  - §7 knot rule: with segment i on [t_i, t_{i+1}], equal angular speed on the circle shared by
//    q_{i−1,1} and q_{i,2} gives t_{i+1} = t_i + (φ_{i,2}/φ_{i−1,1})(t_i − t_{i−1}); the printed
//    φ_{i+1,2}/φ_{i,1} is shifted by one index.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/curves/bezier.h"

namespace se3_interpolation
{
/// The highest `continuity` offered: the contract is C^1 ... C^4 at least; the blending
/// polynomials' properties are tested for every n up to 8 (test_blended_spline).
constexpr int kMaxBlendingContinuity = 8;
/// The degree 2n + 1 of the blending polynomials at the highest continuity.
constexpr std::size_t kMaxBlendingDegree = 2 * kMaxBlendingContinuity + 1;

/// A Bézier polynomial Σ_j c_j b_{d,j}(u) of degree d = 2n + 1 with Pobegailo's control values.
class BlendingPolynomial
{
public:
  /// w_{1,n} (eq. 3.1): increases from 0 to 1; flat to order n at 0, unit slope to order n at 1.
  static BlendingPolynomial increasing(int n) { return BlendingPolynomial(n, true); }
  /// w_{2,n} (eq. 4.1): unit slope to order n at 0, flat zero to order n at 1.
  static BlendingPolynomial decreasing(int n) { return BlendingPolynomial(n, false); }

  int order() const { return n_; }
  int degree() const { return 2 * n_ + 1; }
  /// The control value c_j (j = 0 … 2n + 1).
  double controlValue(int j) const { return control_[static_cast<std::size_t>(j)]; }

  /// The polynomial at u (double or Jet), summed in the Bernstein basis. No allocation: the
  /// powers of u live on the stack (degree ≤ kMaxBlendingDegree), the powers of 1 − u are
  /// accumulated from the highest index down.
  template <class S>
  S operator()(const S& u) const
  {
    const std::size_t d = static_cast<std::size_t>(degree());
    const S v = S(1.0) - u;
    std::array<S, kMaxBlendingDegree + 1> up;
    up[0] = S(1.0);
    for (std::size_t j = 1; j <= d; ++j)
      up[j] = up[j - 1] * u;
    S sum(0.0);
    S vp(1.0);  // v^(d − j)
    for (std::size_t j = d + 1; j-- > 0;)
    {
      if (weight_[j] != 0.0)
        sum += S(weight_[j]) * up[j] * vp;
      vp *= v;
    }
    return sum;
  }

private:
  BlendingPolynomial(int n, bool increasing) : n_(n)
  {
    if (n < 1 || n > kMaxBlendingContinuity)
      throw InvalidInputError("continuity: " + std::to_string(n) + " must be in [1, " +
                              std::to_string(kMaxBlendingContinuity) + "]");
    const int d = 2 * n + 1;
    double binomial = 1.0;  // C(d, j)
    for (int j = 0; j <= d; ++j)
    {
      if (j > 0)
        binomial = binomial * (d - j + 1) / j;
      const bool used = increasing ? j > n : (j >= 1 && j <= n);
      control_[static_cast<std::size_t>(j)] = used ? static_cast<double>(j) / d : 0.0;
      weight_[static_cast<std::size_t>(j)] = binomial * control_[static_cast<std::size_t>(j)];
    }
  }

  int n_;
  std::array<double, kMaxBlendingDegree + 1> control_{};
  std::array<double, kMaxBlendingDegree + 1> weight_{};  ///< C(d, j) c_j
};

/// w_{1,n}(u), eq. 3.1.
template <class S>
S blendingW1(int n, const S& u)
{
  return BlendingPolynomial::increasing(n)(u);
}

/// w_{2,n}(u), eq. 4.1.
template <class S>
S blendingW2(int n, const S& u)
{
  return BlendingPolynomial::decreasing(n)(u);
}

namespace detail
{
/// G::log(p[i], p[j]); an antipodal pair throws NonUniqueGeodesicError naming both points.
template <class G>
typename G::template Tangent<double> namedLog(const std::vector<typename G::template Point<double>>& p, std::size_t i,
                                              std::size_t j, const std::string& label)
{
  try
  {
    return G::log(p[i], p[j]);
  }
  catch (const NonUniqueGeodesicError& e)
  {
    const std::size_t lo = std::min(i, j), hi = std::max(i, j);
    throw NonUniqueGeodesicError(indexedField(label, lo) + " and " + indexedField(label, hi) + ": " + e.what());
  }
}

/// Lagrange basis values ℓ_a(t), ℓ_c(t) of the outer nodes of (ta, tb, tc) (ℓ_b is not needed).
template <class S>
void outerLagrangeBasis(double ta, double tb, double tc, const S& t, S* la, S* lc)
{
  *la = (t - S(tb)) * (t - S(tc)) * S(1.0 / ((ta - tb) * (ta - tc)));
  *lc = (t - S(ta)) * (t - S(tb)) * S(1.0 / ((tc - ta) * (tc - tb)));
}
}  // namespace detail

/// The curve through three points a, b, c at times ta < tb < tc, with the motion that carries
/// its first point along it (see the file comment). Generic version: Lie groups and R^n,
/// C(t) = exp(b, ℓ_a(t) log(b, a) + ℓ_c(t) log(b, c)); motion y ↦ exp(C(t), log(a, y)).
template <class G>
class ThreePointCurve
{
public:
  template <class S>
  using PointT = typename G::template Point<S>;
  using Point = PointT<double>;
  using Tangent = typename G::template Tangent<double>;

  /// log_ba = G::log(b, a), log_bc = G::log(b, c) (computed by the caller, which names the points).
  ThreePointCurve(const Point& a, const Point& b, double ta, double tb, double tc, const Tangent& log_ba,
                  const Tangent& log_bc)
    : a_(a), b_(b), ta_(ta), tb_(tb), tc_(tc), log_ba_(log_ba), log_bc_(log_bc)
  {
  }

  template <class S>
  PointT<S> at(const S& t) const
  {
    S la, lc;
    detail::outerLagrangeBasis(ta_, tb_, tc_, t, &la, &lc);
    using TangentS = typename G::template Tangent<S>;
    const TangentS v = TangentS(log_ba_.template cast<S>() * la) + TangentS(log_bc_.template cast<S>() * lc);
    return G::exp(G::template cast<S>(b_), v);
  }

  /// The motion from a = C(ta) to C(t), applied to y: C(t) ⋆ a⁻¹ ⋆ y.
  template <class S>
  PointT<S> carry(const S& t, const PointT<S>& y) const
  {
    return G::exp(at(t), G::log(G::template cast<S>(a_), y));
  }

private:
  Point a_;
  Point b_;
  double ta_, tb_, tc_;
  Tangent log_ba_;
  Tangent log_bc_;
};

/// On S^m: the circle through a, b, c (SphereCircle, sphere.h), traversed by the rotation
/// exp(θ(t) J) about its centre, θ(t) quadratic with θ(tb) = 0 (see the file comment).
template <>
class ThreePointCurve<Sphere>
{
public:
  template <class S>
  using PointT = Sphere::Point<S>;
  using Point = PointT<double>;
  using Tangent = Sphere::Tangent<double>;

  ThreePointCurve(const Point& a, const Point& b, const Point& c, double ta, double tb, double tc)
    : b_(b), ta_(ta), tb_(tb), tc_(tc), circle_(a, b, c)
  {
  }

  /// The angle θ(t): θ(ta) = θ_a < 0 < θ(tc) = θ_c on a proper circle, θ(tb) = 0.
  template <class S>
  S angle(const S& t) const
  {
    S la, lc;
    detail::outerLagrangeBasis(ta_, tb_, tc_, t, &la, &lc);
    return S(circle_.angleAtFirst()) * la + S(circle_.angleAtLast()) * lc;
  }

  template <class S>
  PointT<S> at(const S& t) const
  {
    return circle_.rotate(angle(t), PointT<S>(b_.template cast<S>()));
  }

  /// exp((θ(t) − θ(ta)) J) y: the rotation carrying a = C(ta) to C(t), applied to y.
  template <class S>
  PointT<S> carry(const S& t, const PointT<S>& y) const
  {
    return circle_.rotate(S(angle(t) - S(circle_.angleAtFirst())), y);
  }

  double angleAtFirst() const { return circle_.angleAtFirst(); }
  double angleAtLast() const { return circle_.angleAtLast(); }

private:
  Point b_;
  double ta_, tb_, tc_;
  SphereCircle circle_;
};

namespace detail
{
template <class G>
ThreePointCurve<G> makeThreePointCurve(const std::vector<typename G::template Point<double>>& x,
                                       const std::vector<double>& t, std::size_t k, const std::string& label)
{
  return ThreePointCurve<G>(x[k], x[k + 1], t[k], t[k + 1], t[k + 2], namedLog<G>(x, k + 1, k, label),
                            namedLog<G>(x, k + 1, k + 2, label));
}

template <>
inline ThreePointCurve<Sphere> makeThreePointCurve<Sphere>(const std::vector<Sphere::Point<double>>& x,
                                                           const std::vector<double>& t, std::size_t k,
                                                           const std::string& /*label*/)
{
  return ThreePointCurve<Sphere>(x[k], x[k + 1], x[k + 2], t[k], t[k + 1], t[k + 2]);
}
}  // namespace detail

/// `blended`: Pobegailo's C^n spline through every waypoint at its time (see the file comment).
template <class G>
class BlendedSpline final : public CurveBase<G, BlendedSpline<G>>
{
public:
  template <class S>
  using PointT = typename G::template Point<S>;
  using Point = PointT<double>;

  /// @param points the waypoints x_0 … x_{N−1} (N ≥ 2), passed at their times
  /// @param times strictly increasing t_0 … t_{N−1} (s)
  /// @param continuity n of C^n, 1 … 8 (the request's `continuity`)
  /// @param label the points' name in error messages (`label[i]`)
  /// @throws InvalidInputError for fewer than 2 points, mismatched or non-increasing times or
  ///         continuity < 1
  /// @throws NonUniqueGeodesicError naming `label[i]` and `label[i+1]` when two consecutive points
  ///         are antipodal
  BlendedSpline(std::vector<Point> points, std::vector<double> times, int continuity,
                const std::string& label = "waypoints")
    : points_(std::move(points))
    , times_(std::move(times))
    , w1_(BlendingPolynomial::increasing(continuity))
    , w2_(BlendingPolynomial::decreasing(continuity))
  {
    if (points_.size() < 2)
      throw InvalidInputError(label + ": " + std::to_string(points_.size()) + " given; at least 2 are needed");
    requireIncreasingTimes(times_, points_.size());
    logs_ = polygonLogs<G>(points_, label);
    for (std::size_t k = 0; k + 2 < points_.size(); ++k)
      curves_.push_back(detail::makeThreePointCurve<G>(points_, times_, k, label));
  }

  template <class S>
  PointT<S> evaluate(const S& t, Side side) const
  {
    const std::size_t n = points_.size();
    const std::size_t i = findInterval(times_, valueOf(t), side);
    if (n == 2)
      return geodesicFromLog<G>(points_[0], logs_[0], S((t - S(times_[0])) * S(1.0 / (times_[1] - times_[0]))));
    if (i == 0)
      return curves_.front().at(t);
    if (i == n - 2)
      return curves_.back().at(t);
    const double h = times_[i + 1] - times_[i];
    const S u = (t - S(times_[i])) * S(1.0 / h);
    const S tau1 = S(times_[i]) + S(h) * w1_(u);
    const S tau2 = S(times_[i]) + S(h) * w2_(u);
    return curves_[i].carry(tau1, curves_[i - 1].at(tau2));
  }

  double startTime() const override { return times_.front(); }
  double endTime() const override { return times_.back(); }
  std::vector<double> breakpoints() const override { return times_; }
  std::vector<Point> controlPoints() const override { return points_; }

  int continuity() const { return w1_.order(); }
  /// C_k, the three-point curve through points k, k+1, k+2 (k = 0 … N − 3).
  const ThreePointCurve<G>& threePointCurve(std::size_t k) const { return curves_.at(k); }

private:
  std::vector<Point> points_;
  std::vector<double> times_;
  BlendingPolynomial w1_;
  BlendingPolynomial w2_;
  std::vector<typename G::template Tangent<double>> logs_;
  std::vector<ThreePointCurve<G>> curves_;
};

}  // namespace se3_interpolation
