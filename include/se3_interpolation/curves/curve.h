// curves/: the constructions, each written once over the geometry G (geometry/): curve.h (this
// header: the Curve<G> interface, time scaling, the times rule), bezier.h (geodesic polygons,
// de Casteljau, Bézier), bspline.h (de Boor), hermite.h (Crouch Case 1), chart_cubic.h (the
// pieces of the C² spline), interpolating_solver.h (its Newton solve), interpolating_spline.h
// (natural / clamped / start), blended_spline.h (Pobegailo C^n), corner_blend.h (blended
// corners of a geodesic polygon), start_join.h (the joining quintic of replanning), chart_hermite.h
// (the two-point Hermite polynomials in a chart that the joining quintic and goal trajectories use).
//
// The curve interface shared by every construction, and time reparameterisation.
//
// A Curve<G> is a map t ↦ G::Point<double> on [startTime(), endTime()] (seconds).
// Concrete curves implement one template `evaluate<S>(const S& t, Side side)`; CurveBase
// turns it into the virtual interface: value(t) in double, and jet(t) in second-order
// Taylor arithmetic, whose coefficients are the exact first and second time
// derivatives (see jet.h). `side` picks the one-sided limit at a breakpoint (a knot or
// waypoint time where a derivative may jump); elsewhere it has no effect.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/geometry/geometry.h"
#include "se3_interpolation/geometry/tangent_space.h"
#include "se3_interpolation/math/jet.h"

namespace se3_interpolation
{
/// The rule of every curve through points at times (and of the request's `times`): one finite
/// time per point, strictly increasing. Throws InvalidInputError naming `times` or times[i].
inline void requireIncreasingTimes(const std::vector<double>& times, std::size_t num_points)
{
  if (times.size() != num_points)
    throw InvalidInputError("times: " + std::to_string(times.size()) + " given for " + std::to_string(num_points) +
                            " waypoints (give one time per waypoint, or none)");
  for (std::size_t i = 0; i < times.size(); ++i)
  {
    if (!std::isfinite(times[i]))
      throw InvalidInputError(indexedField("times", i) + ": " + formatNumber(times[i]) + " is not a finite number");
    if (i > 0 && !(times[i] > times[i - 1]))
      throw InvalidInputError(indexedField("times", i) + ": " + formatNumber(times[i]) + " is not after times[" +
                              std::to_string(i - 1) + "] = " + formatNumber(times[i - 1]) +
                              " (times must be strictly increasing)");
  }
}

/// Scratch space for the recursions: on the stack up to N elements (cubic curves need 4),
/// on the heap beyond; so evaluating a curve of degree ≤ 3 allocates nothing.
template <class T, std::size_t N = 4>
class ScratchBuffer
{
public:
  explicit ScratchBuffer(std::size_t size)
  {
    if (size > N)
      heap_.resize(size);
    data_ = size > N ? heap_.data() : stack_.data();
  }
  ScratchBuffer(const ScratchBuffer&) = delete;
  ScratchBuffer& operator=(const ScratchBuffer&) = delete;
  T& operator[](std::size_t i) { return data_[i]; }

private:
  std::array<T, N> stack_;
  std::vector<T> heap_;
  T* data_ = nullptr;
};

/// Which one-sided limit to take at a breakpoint.
enum class Side
{
  kLeft,
  kRight
};

namespace detail
{
/// A second-order jet's value and first coefficient, for each point type of the geometries.
inline Jet<1> firstOrderOf(const Jet<2>& x)
{
  Jet<1> r(x.value());
  r.coefficient(1) = x.coefficient(1);
  return r;
}
inline VectorX<Jet<1>> firstOrderOf(const VectorX<Jet<2>>& x)
{
  VectorX<Jet<1>> r(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i)
    r[i] = firstOrderOf(x[i]);
  return r;
}
inline Quaternion<Jet<1>> firstOrderOf(const Quaternion<Jet<2>>& q)
{
  return Quaternion<Jet<1>>(firstOrderOf(q.w()), firstOrderOf(q.x()), firstOrderOf(q.y()), firstOrderOf(q.z()));
}
inline Pose<Jet<1>> firstOrderOf(const Pose<Jet<2>>& x)
{
  return Pose<Jet<1>>(firstOrderOf(x.q),
                      Vector3<Jet<1>>(firstOrderOf(x.p[0]), firstOrderOf(x.p[1]), firstOrderOf(x.p[2])));
}
}  // namespace detail

template <class G>
class Curve
{
public:
  using Point = typename G::template Point<double>;
  using Jet1Point = typename G::template Point<Jet<1>>;
  using Jet2Point = typename G::template Point<Jet<2>>;

  virtual ~Curve() = default;
  virtual Point value(double t) const = 0;
  /// The curve at a first-order jet of time (value and velocity), for the measures that need only
  /// speeds (analysis/figures.h, measureLengths). Here the second-order jet at (t, ṫ, 0) with its
  /// last coefficient dropped; every construction of CurveBase computes it directly, with about
  /// half the arithmetic.
  virtual Jet1Point jet1(const Jet<1>& t, Side side = Side::kRight) const
  {
    Jet<2> t2(t.value());
    t2.coefficient(1) = t.coefficient(1);
    return detail::firstOrderOf(jet(t2, side));
  }
  /// The curve at a second-order jet of time: value, velocity and acceleration.
  virtual Jet2Point jet(const Jet<2>& t, Side side = Side::kRight) const = 0;
  virtual double startTime() const = 0;
  virtual double endTime() const = 0;
  /// Sorted times, ends included, between which the curve is analytic.
  virtual std::vector<double> breakpoints() const = 0;
  /// The control polygon (for display); waypoints for interpolating constructions.
  virtual std::vector<Point> controlPoints() const = 0;
};

/// The third-order jets of a curve (value and the first three time derivatives), for the timings
/// that bound jerk (timing/jerk_limited.h). Every construction of CurveBase provides them, as do
/// the wrappers that change a curve's clock; a curve without them (one that forwards only jet())
/// is refused by those timings (jet3Of).
template <class G>
class ThirdOrderJets
{
public:
  using Jet3Point = typename G::template Point<Jet<3>>;

  virtual ~ThirdOrderJets() = default;
  /// The curve at a third-order jet of time (one-sided at a breakpoint).
  virtual Jet3Point jet3(const Jet<3>& t, Side side) const = 0;
};

/// A curve (or a part of one) without third-order jets asked for them.
class NoThirdOrderJetsError : public InvalidInputError
{
public:
  using InvalidInputError::InvalidInputError;
};

/// The third-order jet of a curve at t. Throws NoThirdOrderJetsError when the curve has none.
template <class G>
typename ThirdOrderJets<G>::Jet3Point jet3Of(const Curve<G>& curve, const Jet<3>& t, Side side)
{
  const auto* jets = dynamic_cast<const ThirdOrderJets<G>*>(&curve);
  if (jets == nullptr)
    throw NoThirdOrderJetsError("curve: this curve gives no third derivatives (a timing that bounds jerk needs them)");
  return jets->jet3(t, side);
}

/// CRTP adapter: Derived provides `template <class S> Point<S> evaluate(const S& t, Side) const`.
template <class G, class Derived>
class CurveBase : public Curve<G>, public ThirdOrderJets<G>
{
public:
  using typename Curve<G>::Point;
  using typename Curve<G>::Jet1Point;
  using typename Curve<G>::Jet2Point;
  using typename ThirdOrderJets<G>::Jet3Point;

  Point value(double t) const final { return self().template evaluate<double>(t, Side::kRight); }
  Jet1Point jet1(const Jet<1>& t, Side side) const final { return self().template evaluate<Jet<1>>(t, side); }
  Jet2Point jet(const Jet<2>& t, Side side) const final { return self().template evaluate<Jet<2>>(t, side); }
  Jet3Point jet3(const Jet<3>& t, Side side) const final { return self().template evaluate<Jet<3>>(t, side); }

private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
};

/// Index i of the interval [b_i, b_{i+1}] of sorted breakpoints b containing t.
/// At an interior breakpoint, Side::kLeft gives the interval ending there. Times
/// outside [b_0, b_last] give the first or last interval (extrapolation).
inline std::size_t findInterval(const std::vector<double>& b, double t, Side side)
{
  const std::size_t last = b.size() - 2;
  auto it = side == Side::kRight ? std::upper_bound(b.begin(), b.end(), t) : std::lower_bound(b.begin(), b.end(), t);
  const std::ptrdiff_t i = (it - b.begin()) - 1;
  if (i < 0)
    return 0;
  return std::min(static_cast<std::size_t>(i), last);
}

/// Relative distance within which a time mapped through a wrapper's change of clock (an affine
/// map t ↦ t0 + (t − t0)/k or t ↦ t − offset) counts as the base curve's breakpoint: the maps round
/// by a few ulps of the larger of t and the shift, so the image of a breakpoint maps back beside
/// it; 1e-12 is thousands of ulps above that and far below the 1 ns the planner resolves.
constexpr double kBreakpointSnapRelative = 1e-12;

/// The breakpoints of a base curve, for a wrapper that evaluates it on another clock: a time that
/// maps within rounding of a base breakpoint is moved onto it, so that a one-sided jet at the
/// wrapper's own breakpoint (the image of the base's) takes the side it asks for and not the
/// neighbouring piece.
class BreakpointSnap
{
public:
  BreakpointSnap() = default;
  explicit BreakpointSnap(std::vector<double> breakpoints) : b_(std::move(breakpoints)) {}

  /// The correction that moves u onto the nearest base breakpoint within rounding, or 0.
  double correction(double u) const
  {
    const auto it = std::lower_bound(b_.begin(), b_.end(), u);
    for (auto c : { it, it == b_.begin() ? b_.end() : it - 1 })
      if (c != b_.end() && std::abs(*c - u) <= kBreakpointSnapRelative * std::max(1.0, std::abs(*c)))
        return *c - u;
    return 0.0;
  }
  /// u (a double or a jet of time) moved onto a base breakpoint within rounding.
  template <class S>
  S snap(const S& u) const
  {
    const double d = correction(valueOf(u));
    return d == 0.0 ? u : S(u + S(d));
  }

private:
  std::vector<double> b_;
};

/// A base curve run on another clock: c(t) = base(s(t)), whose jets compose the base curve's with
/// the clock's. A derived class gives the clock s (baseTime, in double and in jets, with the side
/// of the base curve a time maps onto) and the time span; the control points are the base curve's.
template <class G>
class RetimedCurve : public Curve<G>
{
public:
  using typename Curve<G>::Point;
  using typename Curve<G>::Jet2Point;

  Point value(double t) const final { return base_->value(baseTime(t)); }
  Jet2Point jet(const Jet<2>& t, Side side) const final
  {
    Side base_side = side;
    const Jet<2> s = baseTime(t, side, &base_side);
    return base_->jet(s, base_side);
  }
  std::vector<Point> controlPoints() const final { return base_->controlPoints(); }

  /// @return the curve this one runs on another clock
  const Curve<G>& base() const { return *base_; }
  /// @return the same, shared
  const std::shared_ptr<const Curve<G>>& sharedBase() const { return base_; }
  /// The clock: s(t) for a jet of this curve's time t (the composition with an outer clock's jet),
  /// and in *base_side the side of s the base curve is evaluated from (`side` on entry).
  Jet<2> clock(const Jet<2>& t, Side side, Side* base_side) const { return baseTime(t, side, base_side); }

protected:
  /// @param base the curve run on the new clock
  explicit RetimedCurve(std::shared_ptr<const Curve<G>> base) : base_(std::move(base)) {}

  /// @param t a time of this curve (s)
  /// @return s(t), the base curve's time
  virtual double baseTime(double t) const = 0;
  /// @param t the jet of a time of this curve
  /// @param side the side of t that this curve is evaluated from
  /// @param base_side receives the side of s(t) that the base curve is evaluated from (`side` on entry)
  /// @return the jet of s at t
  virtual Jet<2> baseTime(const Jet<2>& t, Side side, Side* base_side) const = 0;

private:
  std::shared_ptr<const Curve<G>> base_;
};

/// A curve run on a uniformly stretched clock: c(t) = base(t0 + (t − t0)/k), k ≥ 1,
/// so velocities scale by 1/k and accelerations by 1/k² (docs/timing.md).
template <class G>
class TimeScaledCurve final : public RetimedCurve<G>, public ThirdOrderJets<G>
{
public:
  using typename ThirdOrderJets<G>::Jet3Point;

  /// @param base the curve to stretch, from its start time
  /// @param scale the stretch k
  TimeScaledCurve(std::shared_ptr<const Curve<G>> base, double scale)
    : RetimedCurve<G>(std::move(base)), t0_(this->base().startTime()), scale_(scale), snap_(this->base().breakpoints())
  {
  }

  /// Throws InvalidInputError when the base curve has no third-order jets.
  Jet3Point jet3(const Jet<3>& t, Side side) const override
  {
    return jet3Of(this->base(), snap_.snap(Jet<3>(t0_) + (t - Jet<3>(t0_)) / Jet<3>(scale_)), side);
  }
  double startTime() const override { return t0_; }
  double endTime() const override { return t0_ + (this->base().endTime() - t0_) * scale_; }
  std::vector<double> breakpoints() const override
  {
    std::vector<double> b = this->base().breakpoints();
    for (double& x : b)
      x = t0_ + (x - t0_) * scale_;
    return b;
  }

private:
  double baseTime(double t) const override { return t0_ + (t - t0_) / scale_; }
  Jet<2> baseTime(const Jet<2>& t, Side /*side*/, Side* /*base_side*/) const override
  {
    return snap_.snap(Jet<2>(t0_) + (t - Jet<2>(t0_)) / Jet<2>(scale_));
  }

  double t0_;
  double scale_;
  BreakpointSnap snap_;
};

/// (T1), (T2) of a curve at time t (one-sided at a breakpoint).
template <class G>
TangentMotion<G> tangentMotion(const Curve<G>& curve, double t, Side side = Side::kRight)
{
  return tangentMotion<G>(curve.jet(Jet<2>::variable(t), side));
}

}  // namespace se3_interpolation
