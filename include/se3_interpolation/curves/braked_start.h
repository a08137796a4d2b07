// Replanning from a state that cannot continue along a curve within the bounds: the start state's
// motion braked to rest along its own directions, then a motion from rest (the planner's
// start-state unit, src/planner/start_state.cpp).
//
// From the start pose (R_0, p_0) with spatial twist (v_0, ω_0) (README, "Conventions"), each
// channel decelerates at a constant rate along its own direction until it stops:
//   p(τ) = p_0 + v̂ s(τ),             s(τ) = |v_0| τ − a τ² / 2   for τ ≤ T_l = |v_0| / a,      (B1)
//   R(τ) = exp(θ(τ) [ŵ]×) R_0,        θ(τ) = |ω_0| τ − α τ² / 2   for τ ≤ T_a = |ω_0| / α,     (B2)
// and holds still after its stop (s(τ) = s(T_l) for τ > T_l, θ likewise). Then ṗ = v̂ ṡ and
// p̈ = −a v̂: the linear speed falls at exactly a, and so does the angular one (a rotation about a
// fixed axis ŵ, whose spatial angular velocity is θ̇ ŵ and acceleration θ̈ ŵ). No motion brings a
// speed down faster under an acceleration bound (d|v|/dt ≥ −|v̇|), so with a and α the acceleration
// bounds the recovery from a start beyond a velocity bound is as fast as the bounds allow. The
// motion is geometry-free (a translation on a line and a rotation about a fixed axis in any of
// the geometries); after the stop at T = max(T_l, T_a) the curve `rest` (a motion from rest at the
// stopping pose) follows on a shifted clock. At τ = 0 from the left the curve has the start
// state's acceleration (the state the motion starts from); from the right the braking's.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/curves/start_join.h"
#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/geometry/pose.h"

namespace se3_interpolation
{
/// One channel's braking (B1, B2): its direction, start speed and constant deceleration.
struct ChannelBrake
{
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  ///< unit, or zero for a channel at rest
  double speed = 0.0;                                   ///< at the start (m/s or rad/s)
  double deceleration = 0.0;                            ///< (m/s² or rad/s²), positive where speed > 0

  /// The time it takes to stop (0 at rest).
  double stopTime() const { return speed > 0.0 ? speed / deceleration : 0.0; }
  /// The distance travelled until the stop: speed² / (2 deceleration).
  double distance() const { return speed > 0.0 ? 0.5 * speed * stopTime() : 0.0; }

  /// The distance along the direction at time τ ≥ 0 since the start (a jet of time or a double).
  template <class S>
  S distanceAt(const S& tau) const
  {
    if (!(speed > 0.0))
      return S(0.0);
    if (valueOf(tau) >= stopTime())
      return S(distance());
    return S(speed) * tau - S(0.5 * deceleration) * tau * tau;
  }
};

/// The stop of a start state (B1, B2): both channels' brakes and the start's acceleration (the
/// first sample's, from the left at τ = 0).
struct BrakeToRest
{
  Pose<double> start;
  ChannelBrake linear;
  ChannelBrake angular;
  Twist start_acceleration;

  /// T = max(T_l, T_a): when both channels have stopped.
  double stopTime() const { return std::max(linear.stopTime(), angular.stopTime()); }

  /// The earlier channel's stop, where its deceleration ends, within (0, T) (empty if none).
  std::vector<double> breakpoints() const
  {
    const double first = std::min(linear.stopTime(), angular.stopTime());
    return first > 0.0 && first < stopTime() ? std::vector<double>{ first } : std::vector<double>{};
  }

  /// The pose where the motion comes to rest.
  Pose<double> stopPose() const
  {
    return Pose<double>(so3Exp<double>(angular.direction * angular.distance()) * start.q,
                        start.p + linear.direction * linear.distance());
  }

  /// The braking motion at τ ∈ [0, T] (a jet of time or a double); `side` kLeft at τ = 0 gives the
  /// start state's acceleration.
  template <class S>
  Pose<S> at(const S& tau, Side side) const
  {
    const Pose<S> x0 = start.template cast<S>();
    if (valueOf(tau) == 0.0 && side == Side::kLeft)
    {
      // The start state itself: p_0 + v_0 τ + a_0 τ²/2, exp(ω_0 τ + α_0 τ²/2) R_0 (at τ = 0: the
      // pose, the twist and the acceleration of the start state, the spatial ω̇ = φ̈ there).
      const Vector3<S> dp = (linear.direction * linear.speed).template cast<S>() * tau +
                            (0.5 * start_acceleration.linear).template cast<S>() * (tau * tau);
      const Vector3<S> phi = (angular.direction * angular.speed).template cast<S>() * tau +
                             (0.5 * start_acceleration.angular).template cast<S>() * (tau * tau);
      return Pose<S>(Quaternion<S>(so3Exp<S>(phi) * x0.q), Vector3<S>(x0.p + dp));
    }
    const Vector3<S> dp = linear.direction.template cast<S>() * linear.distanceAt(tau);
    const Vector3<S> phi = angular.direction.template cast<S>() * angular.distanceAt(tau);
    return Pose<S>(Quaternion<S>(so3Exp<S>(phi) * x0.q), Vector3<S>(x0.p + dp));
  }
};

/// The braking on [0, T] (`Brake`: BrakeToRest's B1, B2, or curves/jerk_brake.h's JerkBrake: its
/// stopTime(), breakpoints() within (0, T) and at(τ, side)), then `rest` (from its start time)
/// shifted to begin at T. Throws InvalidInputError when the braking does not stop in a positive,
/// finite time.
template <class G, class Brake = BrakeToRest>
class BrakedStartCurve final : public CurveBase<G, BrakedStartCurve<G, Brake>>
{
public:
  template <class S>
  using PointT = typename G::template Point<S>;
  using Point = PointT<double>;

  BrakedStartCurve(const Brake& brake, std::shared_ptr<const Curve<G>> rest)
    : brake_(brake), stop_(brake.stopTime()), rest_(std::move(rest)), rest_snap_(rest_->breakpoints())
  {
    if (!(stop_ > 0.0) || !std::isfinite(stop_))
      throw InvalidInputError("start_state: braking it to rest takes " + formatNumber(stop_) +
                              " s (it must be positive and finite)");
  }

  template <class S>
  PointT<S> evaluate(const S& t, Side side) const
  {
    const double tv = valueOf(t);
    if (tv > stop_ || (tv == stop_ && side == Side::kRight))
    {
      S rest_time = rest_snap_.snap(S(t - S(offset())));
      if (tv == endTime())  // the last sample is the rest's end exactly
        rest_time = rest_time + S(rest_->endTime() - valueOf(rest_time));
      return detail::evaluateAt<G>(*rest_, rest_time, side);
    }
    return brake_.at(t, side);
  }
  double startTime() const override { return 0.0; }
  double endTime() const override { return rest_->endTime() + offset(); }
  /// T: when the motion from rest begins.
  double stopTime() const { return stop_; }
  std::vector<double> breakpoints() const override
  {
    std::vector<double> b{ 0.0 };
    for (double x : brake_.breakpoints())
      b.push_back(x);
    b.push_back(stop_);
    for (double x : rest_->breakpoints())
      if (x + offset() > stop_)
        b.push_back(x + offset());
    if (b.back() < endTime())
      b.push_back(endTime());
    return b;
  }
  std::vector<Point> controlPoints() const override
  {
    std::vector<Point> c{ brake_.start };
    for (const Point& x : rest_->controlPoints())
      c.push_back(x);
    return c;
  }

private:
  /// Curve time minus the rest's time after the stop.
  double offset() const { return stop_ - rest_->startTime(); }

  Brake brake_;
  double stop_;
  std::shared_ptr<const Curve<G>> rest_;
  BreakpointSnap rest_snap_;
};
}  // namespace se3_interpolation
