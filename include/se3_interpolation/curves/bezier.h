// Geodesic polygons, the generalised de Casteljau algorithm and Bézier curves.
//
// Richardson's thesis Algorithm 4.1.2: with interp_λ(a, b) = a Exp(λ Log(a⁻¹b)) (eq. 4.1),
//   b_{i,0} = g_i,   b_{i,j} = interp_λ(b_{i,j−1}, b_{i+1,j−1})   (eq. 4.2),
// and the Bézier curve is b_{0,n}(λ). Written once over the geometry G (geometry.h).
// Properties (thesis Prop. 4.2.1–4.2.4, tested): left invariance, affine
// reparameterisation, symmetry under reversed control points, geodesic precision;
// bi-invariance for the screw metric (Cor. 4.2.7). The first level's logarithms do not
// depend on λ and are computed once per curve.
#pragma once

#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/deadline.h"

namespace se3_interpolation
{
/// Log(p_i, p_{i+1}) for each leg of a polygon. An antipodal pair (no unique geodesic)
/// throws NonUniqueGeodesicError naming the two points as `label[i]` and `label[i+1]`.
template <class G>
std::vector<typename G::template Tangent<double>> polygonLogs(const std::vector<typename G::template Point<double>>& p,
                                                              const std::string& label)
{
  std::vector<typename G::template Tangent<double>> logs;
  logs.reserve(p.size() > 0 ? p.size() - 1 : 0);
  for (std::size_t i = 0; i + 1 < p.size(); ++i)
  {
    try
    {
      logs.push_back(G::log(p[i], p[i + 1]));
    }
    catch (const NonUniqueGeodesicError& e)
    {
      throw NonUniqueGeodesicError(indexedField(label, i) + " and " + indexedField(label, i + 1) + ": " + e.what());
    }
  }
  return logs;
}

/// Levels of the de Casteljau recursion between two deadline checks (deadline.h).
constexpr std::size_t kDeCasteljauLevelsPerCheck = 32;

namespace detail
{
/// Whether G has a closed-form jet of scalar S (Jet<1> or Jet<2>) of exp(a, α L) for constant a
/// and L (G::expLine).
template <class G, class S, class = void>
struct HasExpLine : std::false_type
{
};
template <class G, class S>
struct HasExpLine<G, S,
                  std::void_t<decltype(G::expLine(std::declval<const typename G::template Point<double>&>(),
                                                  std::declval<const typename G::template Tangent<double>&>(),
                                                  std::declval<const S&>()))>> : std::true_type
{
};

/// Whether G gives the kinematics of p Exp(λ L) at a second-order jet λ in closed form
/// (G::expLineKinematics: the SE(3) geometries).
template <class G, class = void>
struct HasExpLineKinematics : std::false_type
{
};
template <class G>
struct HasExpLineKinematics<G, std::void_t<decltype(&G::expLineKinematics)>> : std::true_type
{
};
}  // namespace detail

/// p Exp(λ L) with exp evaluated in the scalar S: the generic path of geodesicFromLog, kept
/// callable for the tests that check the closed forms against it.
template <class G, class S>
typename G::template Point<S> geodesicFromLogGeneric(const typename G::template Point<double>& p,
                                                     const typename G::template Tangent<double>& log, const S& lambda)
{
  return G::exp(G::template cast<S>(p), typename G::template Tangent<S>(log * lambda));
}

/// interp_λ(p, p Exp(L)) = p Exp(λ L) with a precomputed L = Log(p, q). At a first- or second-order jet λ
/// (the first de Casteljau / de Boor level when derivatives are sampled), geometries with a
/// closed form (G::expLine: the Lie groups, whose geodesics are one-parameter subgroups) skip
/// the jet arithmetic; the others run exp in jets.
template <class G, class S>
typename G::template Point<S> geodesicFromLog(const typename G::template Point<double>& p,
                                              const typename G::template Tangent<double>& log, const S& lambda)
{
  if constexpr ((std::is_same<S, Jet<1>>::value || std::is_same<S, Jet<2>>::value) && detail::HasExpLine<G, S>::value)
    return G::expLine(p, log, lambda);
  else
    return geodesicFromLogGeneric<G>(p, log, lambda);
}

/// The kinematics (world frame) of p Exp(λ L) at a second-order jet λ: the geometry's closed
/// form where it has one (G::expLineKinematics), else kinematicsFromJet of geodesicFromLog.
template <class G>
Kinematics geodesicKinematicsFromLog(const typename G::template Point<double>& p,
                                     const typename G::template Tangent<double>& log, const Jet<2>& lambda)
{
  if constexpr (detail::HasExpLineKinematics<G>::value)
    return G::expLineKinematics(p, log, lambda);
  else
    return kinematicsFromJet(geodesicFromLog<G>(p, log, lambda));
}

/// The generalised de Casteljau algorithm (thesis Alg. 4.1.2) at parameter λ, with the
/// first level taken from precomputed logs (logs[i] = Log(points[i], points[i+1])).
template <class G, class S>
typename G::template Point<S> deCasteljau(const std::vector<typename G::template Point<double>>& points,
                                          const std::vector<typename G::template Tangent<double>>& logs,
                                          const S& lambda)
{
  const std::size_t n = points.size();
  if (n == 1)
    return G::template cast<S>(points[0]);
  ScratchBuffer<typename G::template Point<S>> b(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i)
    b[i] = geodesicFromLog<G>(points[i], logs[i], lambda);
  for (std::size_t level = 2; level < n; ++level)
  {
    // A Bézier of degree N − 1 costs N²/2 steps per point: long ones check the request's time.
    checkDeadlineEvery(level, kDeCasteljauLevelsPerCheck, "curve 'bezier'");
    for (std::size_t i = 0; i + level < n; ++i)
      b[i] = geodesic<G>(b[i], b[i + 1], lambda);
  }
  return b[0];
}

/// Splits a Bézier control polygon at λ into the polygons of the two halves (the left
/// and right edges of the de Casteljau triangle); each half, reparameterised to [0, 1],
/// is the original curve on [0, λ] and [λ, 1].
template <class G>
void subdivideBezier(const std::vector<typename G::template Point<double>>& points, double lambda,
                     std::vector<typename G::template Point<double>>* left,
                     std::vector<typename G::template Point<double>>* right)
{
  const std::size_t n = points.size();
  std::vector<typename G::template Point<double>> b = points;
  left->assign(1, b.front());
  right->assign(1, b.back());
  for (std::size_t level = 1; level < n; ++level)
  {
    for (std::size_t i = 0; i + level < n; ++i)
      b[i] = geodesic<G>(b[i], b[i + 1], lambda);
    left->push_back(b.front());
    right->push_back(b[n - level - 1]);
  }
  std::reverse(right->begin(), right->end());
}

/// `piecewise_geodesic`: on [t_i, t_{i+1}] the geodesic x_i → x_{i+1}. C⁰; passes all points.
template <class G>
class PiecewiseGeodesic final : public CurveBase<G, PiecewiseGeodesic<G>>
{
public:
  template <class S>
  using PointT = typename G::template Point<S>;
  using Point = PointT<double>;

  /// @param points the polygon's vertices x_0 … x_{N−1} (N ≥ 2), passed at their times
  /// @param times strictly increasing t_0 … t_{N−1}, one per point (s)
  /// @param label the points' name in error messages (`label[i]`)
  /// @throws NonUniqueGeodesicError if two consecutive points have no unique geodesic (antipodal)
  PiecewiseGeodesic(std::vector<Point> points, std::vector<double> times, const std::string& label = "waypoints")
    : points_(std::move(points)), times_(std::move(times)), logs_(polygonLogs<G>(points_, label))
  {
  }

  template <class S>
  PointT<S> evaluate(const S& t, Side side) const
  {
    const std::size_t i = findInterval(times_, valueOf(t), side);
    const S lambda = (t - S(times_[i])) * S(1.0 / (times_[i + 1] - times_[i]));
    return geodesicFromLog<G>(points_[i], logs_[i], lambda);
  }

  /// The kinematics at t (one-sided at a waypoint) without the jets of the pose, for the SE(3)
  /// geometries (geodesicKinematicsFromLog; analysis/kinematics.h's kinematicsAt calls it).
  Kinematics kinematics(double t, Side side) const
  {
    const std::size_t i = findInterval(times_, t, side);
    const double rate = 1.0 / (times_[i + 1] - times_[i]);
    Jet<2> lambda = Jet<2>::variable((t - times_[i]) * rate);
    lambda.coefficient(1) = rate;
    return geodesicKinematicsFromLog<G>(points_[i], logs_[i], lambda);
  }

  double startTime() const override { return times_.front(); }
  double endTime() const override { return times_.back(); }
  std::vector<double> breakpoints() const override { return times_; }
  std::vector<Point> controlPoints() const override { return points_; }

private:
  std::vector<Point> points_;
  std::vector<double> times_;
  std::vector<typename G::template Tangent<double>> logs_;
};

/// `bezier`: one Bézier curve of degree N−1 on [t0, t1], λ = (t − t0)/(t1 − t0).
template <class G>
class BezierCurve final : public CurveBase<G, BezierCurve<G>>
{
public:
  template <class S>
  using PointT = typename G::template Point<S>;
  using Point = PointT<double>;

  /// @param points the control points (N ≥ 2; the curve starts at the first and ends at the last)
  /// @param t0 the start time (λ = 0)
  /// @param t1 the end time (λ = 1), after t0
  /// @param label the points' name in error messages (`label[i]`)
  /// @throws NonUniqueGeodesicError if two consecutive control points are antipodal
  BezierCurve(std::vector<Point> points, double t0, double t1, const std::string& label = "waypoints")
    : points_(std::move(points)), t0_(t0), t1_(t1), logs_(polygonLogs<G>(points_, label))
  {
  }

  template <class S>
  PointT<S> evaluate(const S& t, Side /*side*/) const
  {
    return deCasteljau<G>(points_, logs_, S((t - S(t0_)) * S(1.0 / (t1_ - t0_))));
  }

  double startTime() const override { return t0_; }
  double endTime() const override { return t1_; }
  std::vector<double> breakpoints() const override { return { t0_, t1_ }; }
  std::vector<Point> controlPoints() const override { return points_; }

private:
  std::vector<Point> points_;
  double t0_;
  double t1_;
  std::vector<typename G::template Tangent<double>> logs_;
};

}  // namespace se3_interpolation
