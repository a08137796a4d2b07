// `hermite`: piecewise generalised cubics with Hermite data (Crouch–Kun–Silva Leite,
// §3 Case 1), and the rule that estimates the velocities when a request gives none.
//
// On each segment [t_i, t_{i+1}], h = t_{i+1} − t_i, the curve is the cubic Bézier curve of the
// generalised de Casteljau algorithm (thesis Alg. 4.1.2, bezier.h) in
// λ = (t − t_i)/h with control points
//   b_0 = x_i,  b_1 = exp(x_i, h v_i / 3),  b_2 = exp(x_{i+1}, −h v_{i+1} / 3),  b_3 = x_{i+1},   (H1)
// the tangents v_i in G's representation (velocity (T1), tangent_space.h). Crouch Thm 2.5
// (n = 3; the curve's derivative at λ = 0 is 3 V_0^1 and at λ = 1 is 3 V_2^1, with V_k^1 the
// generator of the geodesic b_k → b_{k+1}) gives, after λ = (t − t_i)/h,
//   velocity at t_i  = (3/h) log(x_i, b_1)      = v_i,
//   velocity at t_{i+1} = −(3/h) log(x_{i+1}, b_2) = v_{i+1},
// since every geodesic here is reversible: exp(a, λ log(a, b)) = exp(b, (1 − λ) log(b, a)).
// So the curve passes every x_i at t_i with velocity v_i from both sides: C¹.
// (H1) needs log(x, exp(x, u)) = u for u = ±h v/3: for rotations, |u| below π rad. A tangent
// too large for its segment is rejected, naming it.
//
// Velocity estimation when none are given (estimateTangents): in the tangent space at x_i,
// with L⁻ = log(x_i, x_{i−1}), L⁺ = log(x_i, x_{i+1}), h⁻ = t_i − t_{i−1}, h⁺ = t_{i+1} − t_i,
//   v_i = [ h⁻ (L⁺ / h⁺) + h⁺ (−L⁻ / h⁻) ] / (h⁻ + h⁺)                                      (H2)
// — the derivative at t_i of the quadratic through the three points in that chart (exact for
// quadratic motions in R^n; Catmull–Rom's (x_{i+1} − x_{i−1})/(2h) for uniform times), and at
// the ends the one-sided geodesic velocity v_0 = L⁺/h⁺ at x_0, v_{N−1} = −L⁻/h⁻ at x_{N−1}.
#pragma once

#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/geometry/tangent_space.h"

namespace se3_interpolation
{
namespace detail
{
/// At least two points, one finite time per point, strictly increasing; all points with the
/// same tangent dimension. Messages name `waypoints` / `times` and the index.
template <class G>
Eigen::Index requireSplineData(const std::vector<typename G::template Point<double>>& points,
                               const std::vector<double>& times)
{
  if (points.size() < 2)
    throw InvalidInputError("waypoints: " + std::to_string(points.size()) + " given; at least 2 are needed");
  requireIncreasingTimes(times, points.size());
  const Eigen::Index dim = tangentDimension<G>(points[0]);
  for (std::size_t i = 1; i < points.size(); ++i)
    if (tangentDimension<G>(points[i]) != dim)
      throw InvalidInputError(indexedField("waypoints", i) + ": has a different dimension from waypoints[0]");
  return dim;
}

/// A finite tangent of G's dimension at x that lies in T_x (for the sphere: orthogonal to x).
template <class G>
void requireTangent(const typename G::template Point<double>& x, const typename G::template Tangent<double>& v,
                    Eigen::Index dim, const std::string& field)
{
  if (v.size() != dim)
    throw InvalidInputError(field + ": has " + std::to_string(v.size()) + " components; expected " +
                            std::to_string(dim));
  if (!v.allFinite())
    throw InvalidInputError(field + ": is not finite");
  if (!TangentFrame<G>::kIdentity)
  {
    const Eigen::MatrixXd b = TangentFrame<G>::basis(x);
    const Eigen::VectorXd vx = v;
    if ((vx - b * (b.transpose() * vx)).norm() > 1e-9 * (1.0 + vx.norm()))
      throw InvalidInputError(field + ": is not a tangent vector at its point (it has a normal component)");
  }
}

/// exp(x, u) for a Bézier control point, rejecting u too large for log to recover it.
template <class G>
typename G::template Point<double> controlPointFrom(const typename G::template Point<double>& x,
                                                    const typename G::template Tangent<double>& u,
                                                    const std::string& field, std::size_t segment)
{
  const typename G::template Point<double> b = G::exp(x, u);
  bool ok = allFinite(b);
  if (ok)
  {
    try
    {
      ok = (G::log(x, b) - u).norm() <= 1e-9 * (1.0 + u.norm());
    }
    catch (const NonUniqueGeodesicError&)
    {
      ok = false;
    }
  }
  if (!ok)
    throw InvalidInputError(field + ": too large for segment " + std::to_string(segment) +
                            ": the control point exp(x, +/-h v/3) is half a turn or more away, where the "
                            "geodesic from the waypoint no longer reaches it (|h v/3| must stay below pi rad)");
  return b;
}

}  // namespace detail

/// `hermite`: the piecewise generalised cubic (H1) through x_i at t_i with velocity v_i. C¹.
template <class G>
class HermiteSpline final : public CurveBase<G, HermiteSpline<G>>
{
public:
  template <class S>
  using PointT = typename G::template Point<S>;
  using Point = PointT<double>;
  using Tangent = typename G::template Tangent<double>;

  /// @param points the waypoints x_0 … x_{N−1} (N ≥ 2), passed at their times
  /// @param times strictly increasing t_0 … t_{N−1} (s)
  /// @param tangents the velocity v_i at each waypoint, in G's tangent representation at x_i
  /// @param tangent_label names the tangents in error messages (e.g. "velocities" → "velocities[3]")
  /// @throws InvalidInputError for mismatched sizes or dimensions, non-finite or non-tangent
  ///         velocities, or a velocity too large for its segment
  /// @throws NonUniqueGeodesicError if a segment has no unique geodesic
  HermiteSpline(std::vector<Point> points, std::vector<double> times, std::vector<Tangent> tangents,
                const std::string& tangent_label = "velocities")
    : points_(std::move(points)), times_(std::move(times)), tangents_(std::move(tangents))
  {
    const Eigen::Index dim = detail::requireSplineData<G>(points_, times_);
    if (tangents_.size() != points_.size())
      throw InvalidInputError(tangent_label + ": " + std::to_string(tangents_.size()) + " given for " +
                              std::to_string(points_.size()) + " waypoints (one per waypoint)");
    for (std::size_t i = 0; i < points_.size(); ++i)
      detail::requireTangent<G>(points_[i], tangents_[i], dim, indexedField(tangent_label, i));
    polygonLogs<G>(points_, "waypoints");  // antipodal neighbours: an error naming both
    for (std::size_t i = 0; i + 1 < points_.size(); ++i)
    {
      const double h = times_[i + 1] - times_[i];
      std::vector<Point> b{ points_[i],
                            detail::controlPointFrom<G>(points_[i], Tangent(tangents_[i] * (h / 3.0)),
                                                        indexedField(tangent_label, i), i),
                            detail::controlPointFrom<G>(points_[i + 1], Tangent(tangents_[i + 1] * (-h / 3.0)),
                                                        indexedField(tangent_label, i + 1), i),
                            points_[i + 1] };
      try
      {
        logs_.push_back(polygonLogs<G>(b, "b"));
      }
      catch (const NonUniqueGeodesicError& e)
      {
        throw NonUniqueGeodesicError(indexedField(tangent_label, i) + " and " + indexedField(tangent_label, i + 1) +
                                     ": two control points of segment " + std::to_string(i) +
                                     " are antipodal, so the cubic is not defined (" + e.what() + ")");
      }
      segments_.push_back(std::move(b));
    }
  }

  template <class S>
  PointT<S> evaluate(const S& t, Side side) const
  {
    const std::size_t i = findInterval(times_, valueOf(t), side);
    const S lambda = (t - S(times_[i])) * S(1.0 / (times_[i + 1] - times_[i]));
    return deCasteljau<G>(segments_[i], logs_[i], lambda);
  }

  double startTime() const override { return times_.front(); }
  double endTime() const override { return times_.back(); }
  std::vector<double> breakpoints() const override { return times_; }
  /// The Bézier polygon x_0, b_1, b_2, x_1, b_1', … (3N − 2 points).
  std::vector<Point> controlPoints() const override
  {
    std::vector<Point> c{ points_.front() };
    for (const auto& s : segments_)
      c.insert(c.end(), s.begin() + 1, s.end());
    return c;
  }
  const std::vector<Tangent>& tangents() const { return tangents_; }

private:
  std::vector<Point> points_;
  std::vector<double> times_;
  std::vector<Tangent> tangents_;
  std::vector<std::vector<Point>> segments_;
  std::vector<std::vector<Tangent>> logs_;
};

/// The velocities (H2) for a Hermite spline through `points` at `times`.
template <class G>
std::vector<typename G::template Tangent<double>> estimateTangents(
    const std::vector<typename G::template Point<double>>& points, const std::vector<double>& times)
{
  using Tangent = typename G::template Tangent<double>;
  detail::requireSplineData<G>(points, times);
  polygonLogs<G>(points, "waypoints");
  const std::size_t n = points.size();
  std::vector<Tangent> v(n);
  v.front() = G::log(points[0], points[1]) / (times[1] - times[0]);
  v.back() = G::log(points[n - 1], points[n - 2]) / (-(times[n - 1] - times[n - 2]));
  for (std::size_t i = 1; i + 1 < n; ++i)
  {
    const double hm = times[i] - times[i - 1];
    const double hp = times[i + 1] - times[i];
    const Tangent forward = G::log(points[i], points[i + 1]) / hp;
    const Tangent backward = G::log(points[i], points[i - 1]) / (-hm);
    v[i] = (hm * forward + hp * backward) / (hm + hp);
  }
  return v;
}

}  // namespace se3_interpolation
