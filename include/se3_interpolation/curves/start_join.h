// Replanning from a moving state: the joining segment from a given start state (pose, velocity,
// acceleration) into a curve, C² at both of its ends, written once over the geometry G.
//
// Given the start point x_s with its second-order jet X_s(τ) (the pose, velocity and acceleration
// of the motion being replaced, τ = t − t_s), a curve R and the time t_r at which the motion is to
// continue on R, the joining segment on [t_s, t_s + h] is the quintic in the chart at x_s
//   J(t) = G::exp(x_s, P(t − t_s)),   P(τ) = Σ_{k=0}^{5} c_k τ^k ∈ T_{x_s},                       (J1)
// with the six conditions of a quintic Hermite interpolant (the chart's Taylor coefficients):
//   (c_0, c_1, c_2)              = the jet of τ ↦ G::log(x_s, X_s(τ)) at 0,
//   (P(h), P'(h), P''(h)/2)      = the jet of τ ↦ G::log(x_s, R(t_r + τ)) at 0 = (E_0, E_1, E_2),
// which, with A = E_0 − c_0 − c_1 h − c_2 h², B = (E_1 − c_1 − 2 c_2 h) h, C = (E_2 − c_2) h²,
// gives
//   c_3 h³ = 10 A − 4 B + C,   c_4 h⁴ = −15 A + 7 B − 2 C,   c_5 h⁵ = 6 A − 3 B + C           (J2)
// (the classical quintic Hermite basis, written in the monomials: chartHermite of chart_hermite.h). G::exp(x_s, ·) inverts
// G::log(x_s, ·) as a map, so it inverts it on jets too: J has at t_s the value, velocity and
// acceleration of X_s and at t_s + h those of R at t_r, i.e. the joined motion is C² at the
// switch and at the joint, to rounding, whatever the curve R (and in any geometry whose log at x_s
// is smooth near both ends: rotations below π from x_s). In the abelian cases (R^n, pure
// translations, rotations about one axis) the chart is linear and (J1) is the classical quintic
// Hermite polynomial; this is how the geometry-free construction is tested.
//
// After the joint the motion is R shifted in time: c(t) = R(t − (t_s + h) + t_r) for t ≥ t_s + h.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "se3_interpolation/curves/chart_hermite.h"
#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/geometry/geometry.h"

namespace se3_interpolation
{
namespace detail
{
/// A curve evaluated at a double or a jet of time (the two faces of the virtual interface).
template <class G>
typename G::template Point<double> evaluateAt(const Curve<G>& c, double t, Side /*side*/)
{
  return c.value(t);
}
template <class G>
typename G::template Point<Jet<1>> evaluateAt(const Curve<G>& c, const Jet<1>& t, Side side)
{
  return c.jet1(t, side);
}
template <class G>
typename G::template Point<Jet<2>> evaluateAt(const Curve<G>& c, const Jet<2>& t, Side side)
{
  return c.jet(t, side);
}
template <class G>
typename G::template Point<Jet<3>> evaluateAt(const Curve<G>& c, const Jet<3>& t, Side side)
{
  return jet3Of(c, t, side);
}
}  // namespace detail

/// The joining segment (J1) on [start_time, start_time + duration] followed by `rest` from
/// `rest_from` on. Throws InvalidInputError for a duration that is not positive and finite,
/// NonUniqueGeodesicError when R(rest_from) is half a turn from x_s.
template <class G>
class StartJoinedCurve final : public CurveBase<G, StartJoinedCurve<G>>
{
public:
  template <class S>
  using PointT = typename G::template Point<S>;
  using Point = PointT<double>;
  using Tangent = typename G::template Tangent<double>;

  StartJoinedCurve(const Point& start, const PointT<Jet<2>>& start_jet, double start_time, double duration,
                   std::shared_ptr<const Curve<G>> rest, double rest_from)
    : start_(start)
    , t0_(start_time)
    , h_(duration)
    , rest_(std::move(rest))
    , rest_from_(rest_from)
    , rest_snap_(rest_->breakpoints())
  {
    if (!(h_ > 0.0) || !std::isfinite(h_))
      throw InvalidInputError("times: the segment from the start state to the first waypoint lasts " +
                              formatNumber(h_) + " s (it must be positive)");
    const auto c = chartJet<G>(start_, start_jet);
    std::array<Tangent, 3> e;
    try
    {
      e = chartJet<G>(start_, rest_->jet(Jet<2>::variable(rest_from_), Side::kRight));
    }
    catch (const NonUniqueGeodesicError&)
    {
      throw NonUniqueGeodesicError(
          "waypoints[0]: the curve's start is half a turn from the start state's "
          "orientation, so the joining segment is not unique");
    }
    coefficients_ = chartHermite<G>(c, e, h_, 2);
    if (!finiteCoefficients<G>(coefficients_))
      throw InvalidInputError("times: the segment from the start state to the first waypoint lasts " +
                              formatNumber(h_) +
                              " s, too short for its start velocity and the curve it joins "
                              "(the joining polynomial overflows); give the first waypoint a later time");
  }

  template <class S>
  PointT<S> evaluate(const S& t, Side side) const
  {
    const double tv = valueOf(t);
    const double joint = t0_ + h_;
    if (tv > joint || (tv == joint && side == Side::kRight))
    {
      S rest_time = rest_snap_.snap(S(t - S(offset())));
      // The end maps onto the rest's end exactly (t0 + h + (end - from) - offset may round past it,
      // and the curve would be extrapolated there): the last sample is the last waypoint exactly.
      if (tv == endTime())
        rest_time = rest_time + S(rest_->endTime() - valueOf(rest_time));
      return detail::evaluateAt<G>(*rest_, rest_time, side);
    }
    return chartPolynomialAt<G>(start_, coefficients_, kMaxChartHermiteDegree, S(t - S(t0_)));
  }

  double startTime() const override { return t0_; }
  double endTime() const override { return rest_->endTime() + offset(); }
  double jointTime() const { return t0_ + h_; }
  std::vector<double> breakpoints() const override
  {
    std::vector<double> b{ t0_, t0_ + h_ };
    for (double x : rest_->breakpoints())
      if (x > rest_from_)
        b.push_back(x + offset());
    if (b.size() < 3 || b.back() < endTime())
      b.push_back(endTime());
    return b;
  }
  std::vector<Point> controlPoints() const override
  {
    std::vector<Point> c{ start_ };
    for (const Point& x : rest_->controlPoints())
      c.push_back(x);
    return c;
  }

private:
  /// Curve time minus the rest's time after the joint (0 when the rest continues on the same clock).
  double offset() const { return t0_ + h_ - rest_from_; }

  Point start_;
  double t0_;
  double h_;
  std::shared_ptr<const Curve<G>> rest_;
  double rest_from_;
  BreakpointSnap rest_snap_;
  ChartPolynomial<G> coefficients_;
};

}  // namespace se3_interpolation
