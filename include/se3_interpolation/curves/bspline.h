// Geodesic B-splines: the generalised de Boor algorithm and knot insertion.
//
// Knot vector convention (standard, as in Piegl & Tiller): for N control points
// d_0 … d_{N−1} and degree m, knots u_0 ≤ … ≤ u_{N+m} (length N + m + 1); the curve is
// defined on [u_m, u_N]. Interior knots (strictly inside (u_m, u_N)) have multiplicity
// ≤ m, so the curve is C^{m−μ} there; no knot value repeats more than m + 1 times.
//
// De Boor (thesis Alg. 4.3.3, re-indexed to this convention): for t in the span
// [u_k, u_{k+1}), P_j = d_{k−m+j} (j = 0 … m) and for r = 1 … m, j = m … r:
//   α = (t − u_{k−m+j}) / (u_{k+1+j−r} − u_{k−m+j}),   P_j ← interp_α(P_{j−1}, P_j);
// the point is P_m. In R^n this is the classical algorithm; on a group each affine
// combination becomes a geodesic interpolation (eq. 4.7).
//
// Knot insertion (Boehm; thesis ch. 6): inserting u* in [u_k, u_{k+1}) replaces
// d_{k−m+1} … d_k by Q_i = interp_{α_i}(d_{i−1}, d_i), α_i = (u* − u_i)/(u_{i+m} − u_i).
// In R^n the curve is unchanged; on a curved group it moves slightly (the thesis'
// Menelaus question; docs/curves.md gives measured figures).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/curves/bezier.h"

namespace se3_interpolation
{
/// Clamped uniform knots on [t0, t1]: m + 1 copies of each end, N − m − 1 interior knots.
inline std::vector<double> clampedUniformKnots(std::size_t num_points, int degree, double t0, double t1)
{
  const std::size_t m = static_cast<std::size_t>(degree);
  std::vector<double> u(num_points + m + 1);
  const std::size_t spans = num_points - m;
  for (std::size_t i = 0; i < u.size(); ++i)
  {
    if (i <= m)
      u[i] = t0;
    else if (i >= num_points)
      u[i] = t1;
    else
      u[i] = t0 + (t1 - t0) * static_cast<double>(i - m) / static_cast<double>(spans);
  }
  return u;
}

/// Throws InvalidInputError naming `field` unless `knots` is a valid knot vector for
/// `num_points` control points of degree `degree` (see the file comment).
inline void validateKnots(const std::vector<double>& knots, std::size_t num_points, int degree,
                          const std::string& field = "knots")
{
  const std::size_t m = static_cast<std::size_t>(degree);
  const std::size_t expected = num_points + m + 1;
  if (knots.size() != expected)
    throw InvalidInputError(field + ": has " + std::to_string(knots.size()) + " knots; expected " +
                            std::to_string(expected) + " (number of waypoints " + std::to_string(num_points) +
                            " + degree " + std::to_string(degree) + " + 1)");
  for (std::size_t i = 0; i < knots.size(); ++i)
  {
    if (!std::isfinite(knots[i]))
      throw InvalidInputError(indexedField(field, i) + ": is not finite");
    if (i > 0 && knots[i] < knots[i - 1])
      throw InvalidInputError(indexedField(field, i) + ": knots must be non-decreasing (" + std::to_string(knots[i]) +
                              " < " + std::to_string(knots[i - 1]) + ")");
  }
  if (!(knots[m] < knots[num_points]))
    throw InvalidInputError(field + ": the curve's domain [knots[" + std::to_string(m) + "], knots[" +
                            std::to_string(num_points) + "]] is empty");
  for (std::size_t i = 0; i < knots.size();)
  {
    std::size_t j = i;
    while (j < knots.size() && knots[j] == knots[i])
      ++j;
    const std::size_t mult = j - i;
    const bool interior = knots[i] > knots[m] && knots[i] < knots[num_points];
    if ((interior && mult > m) || mult > m + 1)
      throw InvalidInputError(indexedField(field, i) + ": knot " + std::to_string(knots[i]) + " has multiplicity " +
                              std::to_string(mult) + "; at most " + std::to_string(interior ? m : m + 1) +
                              (interior ? " inside the domain" : ""));
    i = j;
  }
}

/// Span index k with u_k ≤ t < u_{k+1} (Side::kRight) or u_k < t ≤ u_{k+1} (Side::kLeft),
/// clamped to the domain's non-empty spans among m … N−1 (at or beyond a domain end, the
/// limit from inside the domain).
inline std::size_t knotSpan(const std::vector<double>& u, std::size_t num_points, int degree, double t, Side side)
{
  auto it = side == Side::kRight ? std::upper_bound(u.begin(), u.end(), t) : std::lower_bound(u.begin(), u.end(), t);
  std::ptrdiff_t k = (it - u.begin()) - 1;
  const std::ptrdiff_t first = degree;
  const std::ptrdiff_t last = static_cast<std::ptrdiff_t>(num_points) - 1;
  // Clamped to the domain, the span can be empty when a domain end is a repeated knot
  // (e.g. u_{N−1} = u_N): take the nearest non-empty span inside the domain.
  auto empty = [&u](std::ptrdiff_t s) {
    return !(u[static_cast<std::size_t>(s)] < u[static_cast<std::size_t>(s) + 1]);
  };
  if (k >= last)
  {
    k = last;
    while (k > first && empty(k))
      --k;
  }
  else if (k <= first)
  {
    k = first;
    while (k < last && empty(k))
      ++k;
  }
  return static_cast<std::size_t>(k);
}

/// The generalised de Boor algorithm at t in span k (first level from precomputed logs).
template <class G, class S>
typename G::template Point<S> deBoor(const std::vector<typename G::template Point<double>>& d,
                                     const std::vector<typename G::template Tangent<double>>& logs,
                                     const std::vector<double>& u, int degree, std::size_t k, const S& t)
{
  const std::size_t m = static_cast<std::size_t>(degree);
  ScratchBuffer<typename G::template Point<S>> p(m + 1);
  // Level r = 1 from the control points: P_j = interp_α(d_{k−m+j−1}, d_{k−m+j}).
  for (std::size_t j = 1; j <= m; ++j)
  {
    const std::size_t i = k - m + j;
    const S alpha = (t - S(u[i])) * S(1.0 / (u[i + m] - u[i]));
    p[j] = geodesicFromLog<G>(d[i - 1], logs[i - 1], alpha);
  }
  for (std::size_t r = 2; r <= m; ++r)
    for (std::size_t j = m; j >= r; --j)
    {
      const std::size_t i = k - m + j;
      const S alpha = (t - S(u[i])) * S(1.0 / (u[i + m + 1 - r] - u[i]));
      p[j] = geodesic<G>(p[j - 1], p[j], alpha);
    }
  return m == 0 ? G::template cast<S>(d[k]) : p[m];
}

/// `bspline`: a geodesic B-spline of degree m on a knot vector (default clamped uniform).
template <class G>
class BSplineCurve final : public CurveBase<G, BSplineCurve<G>>
{
public:
  template <class S>
  using PointT = typename G::template Point<S>;
  using Point = PointT<double>;

  /// @param control the control points d_0 … d_{N−1}
  /// @param degree m, 1 ≤ m ≤ N − 1
  /// @param knots N + m + 1 non-decreasing knots (e.g. clampedUniformKnots()); the curve lives on
  ///        [knots[m], knots[N]]
  /// @param label the control points' name in error messages (`label[i]`)
  /// @throws InvalidInputError naming `knots` if the knot vector is invalid (see validateKnots())
  /// @throws NonUniqueGeodesicError if two consecutive control points are antipodal
  BSplineCurve(std::vector<Point> control, int degree, std::vector<double> knots,
               const std::string& label = "waypoints")
    : control_(std::move(control)), degree_(degree), knots_(std::move(knots)), logs_(polygonLogs<G>(control_, label))
  {
    validateKnots(knots_, control_.size(), degree_);
  }

  template <class S>
  PointT<S> evaluate(const S& t, Side side) const
  {
    const std::size_t k = knotSpan(knots_, control_.size(), degree_, valueOf(t), side);
    return deBoor<G>(control_, logs_, knots_, degree_, k, t);
  }

  double startTime() const override { return knots_[static_cast<std::size_t>(degree_)]; }
  double endTime() const override { return knots_[control_.size()]; }
  std::vector<double> breakpoints() const override
  {
    std::vector<double> b;
    for (std::size_t i = static_cast<std::size_t>(degree_); i <= control_.size(); ++i)
      if (b.empty() || knots_[i] > b.back())
        b.push_back(knots_[i]);
    return b;
  }
  std::vector<Point> controlPoints() const override { return control_; }
  const std::vector<double>& knots() const { return knots_; }
  int degree() const { return degree_; }

  /// Boehm's knot insertion with geodesic interpolation: the spline with `knot` added.
  BSplineCurve insertKnot(double knot) const
  {
    const std::size_t m = static_cast<std::size_t>(degree_);
    const std::size_t k = knotSpan(knots_, control_.size(), degree_, knot, Side::kRight);
    std::vector<Point> q;
    q.reserve(control_.size() + 1);
    for (std::size_t i = 0; i <= k - m; ++i)
      q.push_back(control_[i]);
    for (std::size_t i = k - m + 1; i <= k; ++i)
    {
      const double alpha = (knot - knots_[i]) / (knots_[i + m] - knots_[i]);
      q.push_back(geodesicFromLog<G>(control_[i - 1], logs_[i - 1], alpha));
    }
    for (std::size_t i = k; i < control_.size(); ++i)
      q.push_back(control_[i]);
    std::vector<double> u = knots_;
    u.insert(u.begin() + static_cast<std::ptrdiff_t>(k) + 1, knot);
    return BSplineCurve(std::move(q), degree_, std::move(u), "control points");
  }

private:
  std::vector<Point> control_;
  int degree_;
  std::vector<double> knots_;
  std::vector<typename G::template Tangent<double>> logs_;
};

}  // namespace se3_interpolation
