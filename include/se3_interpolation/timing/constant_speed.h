// timing/: constant_speed.h (this header): a constant chord speed between a start and a stop ramp
// (timing `constant_speed`, the process speed of gluing, welding, painting or inspection).
//
// The path C(s) and its channels are those of time_optimal.h and jerk_limited.h. Its chord speed
// per unit path parameter is
//   g(s) = √(w_lin |p′|² + w_ang |ω_s|²)         (w = (1, ρ²), ρ = rotation_scale)            (1)
// so that the motion's chord speed √(|ṗ|² + ρ²|ω|²) is g(s) ṡ, and its chord arc length
// σ(s) = ∫ g ds runs from 0 to L. The timing is written in σ:
//   ramp up    σ(t) = V T_u P((t − t_0)/T_u),              t_0 ≤ t ≤ t_a = t_0 + T_u
//   cruise     σ(t) = σ_a + V (t − t_a),                   σ_a = V T_u / 2, up to σ_b = L − V T_d / 2
//   ramp down  σ(t) = L − V T_d P((t_e − t)/T_d),           t_e − T_d ≤ t ≤ t_e
// (from a moving start, the ramp up rises from the start's chord speed v_0 and acceleration a_0:
// σ̇ = v_0 + (V − v_0) P′(τ) + a_0 T_u H₁(τ), H₁ the quintic Hermite basis of the slope at 0, so
// σ_a = T_u (V + v_0)/2 + a_0 T_u²/10; a ramp whose σ̇ would not stay positive is refused naming
// `start_state`) with P(τ) = τ⁴ (5/2 − 3τ + τ²), whose derivative is the quintic smoothstep
// P′(τ) = 10τ³ − 15τ⁴ + 6τ⁵ (rising from 0 to 1 with zero first and second derivatives at both
// ends, ∫₀¹ P′ = ½): the chord speed rises from rest to V and falls back with continuous
// acceleration and jerk (σ̈ = V P″/T, σ⃛ = V P‴/T², zero at both ends of a ramp; on a straight
// line the peak acceleration is 15/8 V/T and the peak jerk 10/√3 V/T²). Between the ramps the
// chord speed is V: the constant-speed window [t_a, t_e − T_d].
//
// The path parameter at σ, s = S(σ) (the inverse of σ(s)), is a piecewise quintic in σ: on a grid of
// the path (its breakpoints, then 2 intervals_per_piece uniform intervals per analytic piece and at
// least 2 min_intervals in all: the quintic's slope is off by about 1e-6 at 16 intervals per piece of
// a cubic spline and 1e-7 at 32, falling as h⁵) σ at the grid points comes from 4-point
// Gauss–Legendre quadrature of g, and on each interval the quintic Hermite interpolant matches S, S′ = 1/g and S″ = −g′/g³ at
// both ends (one-sided where C″ jumps; g′ = Σ w C′·C″ / g). An interval whose chord speed
// g(S(σ)) S′(σ) is off 1 by more than kChordSpeedTolerance where the slope error of such an
// interpolant peaks (u/h = ½ ∓ 1/(2√5): the error is ∝ u³(u − h)³) is halved (at most
// kMaxChordSplits times), so the motion is C² in time, its jets are the exact derivatives of its
// own positions, and its chord speed in the window is V to that tolerance (measured by the check
// and reported as chord_speed_deviation).
//
// Ramps: T_u and T_d start at the straight line's shortest, max(15/8 V/a, √(10/√3 V/j)) with
// a = min(a_lin, ρ a_ang) and j = min(j_lin, ρ j_ang) over the bounds given, and each is lengthened by
// the root of its worst excess (√ of an acceleration's ratio to its bound, ∛ of a jerk's: at a
// given fraction of the ramp accelerations scale as 1/T and jerks as 1/T², the bend's share aside)
// until every bound holds on its ramp (at most kMaxRampPasses times). Where a ramp would need the
// whole path (σ_a > σ_b), the request is refused naming `speed`.
//
// Refusals (InvalidInputError naming the field and the path parameter s, the path time): a chord
// speed that vanishes somewhere (the path stands still there: a clamped end at rest, a dwell, a
// cusp), where no finite path speed gives the chord speed V, names `speed`; a velocity corner
// (C′ jumps) needs an infinite acceleration at any speed and names the acceleration bound of the
// channel that turns; with a jerk bound, a jump of C″ inside the window (a path that is only C¹
// there: hermite, blended continuity 1, a B-spline whose acceleration jumps at a knot) is an
// infinite jerk and names the jerk bound; and a bound that holding V breaks between the shortest
// ramps (checked before the ramps are fitted, which only lengthens them and shortens the cruise: a
// speed above max_*_velocity, the centripetal acceleration V²κ of a bend, the jerk of a tightening
// bend) names that bound. The speed is thus one the path can be passed at outside its shortest ramps.
//
// Verification: every piece of the check (every second interval of the table: time_optimal's grid),
// mapped to the times it is passed (and halved where a bounded rate near its bound varies by more than
// a quarter across it: uneven waypoint times), is evaluated at its two ends (one-sided) and its middle with exact path jets (third-order ones when a jerk bound is set:
// j = C‴ṡ³ + 3C″ṡs̈ + C′s⃛, jerk_limited.h eq. 1), and searched for its interior maximum where a
// rate or the parabola through its three values comes within kNearBound of its bound (a rate flat to
// rounding over a piece is not: the chord speed itself); the cruise is checked once between the
// shortest ramps (a bound broken there refuses the speed), each ramp as it is fitted, and the motion
// as fitted for the figures (max_speed, max_acceleration, max_jerk: the peaks found, the unbounded
// rates searched where the parabola peaks inside; acceleration_energy by Simpson's rule on the pieces).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/timing/jerk_limited.h"
#include "se3_interpolation/timing/time_optimal.h"

namespace se3_interpolation
{
namespace timing
{
/// The chord speed's relative error (|g(S(σ)) S′(σ) − 1|) above which an interval of S is halved.
constexpr double kChordSpeedTolerance = 1e-7;
/// Halvings of one interval of S at most (a factor 2¹⁶ below the grid).
constexpr int kMaxChordSplits = 16;
/// A grid point whose chord speed g is below this fraction of the path's largest is a stand-still.
constexpr double kStandStillFraction = 1e-9;
/// Lengthenings of a ramp at most before the request is refused.
constexpr int kMaxRampPasses = 40;

/// What the constant-speed timing needs besides the bounds.
struct ConstantSpeedOptions
{
  double speed = 0.0;                        ///< V, the chord speed of the window (m/s)
  std::array<double, 2> metric{ 1.0, 1.0 };  ///< w_lin, w_ang of eq. 1 (poses: 1 and ρ²)
  /// The check's grid (as time_optimal's); the table of S has twice as many intervals.
  std::size_t intervals_per_piece = 16;
  std::size_t min_intervals = 512;
  /// Start moving, at the path's own speed at its start (ṡ = 1, s̈ = 0: a path whose clock at its
  /// start is the start state's, like the joined curve of a replan): the ramp rises from the chord
  /// speed g(s_0) and chord acceleration g′(s_0) to V instead of from rest (file comment).
  bool continue_start = false;
};

/// The ramp's shape P(τ) = τ⁴ (5/2 − 3τ + τ²) on [0, 1] (a double or a jet).
template <class S>
S rampShape(const S& tau)
{
  return tau * tau * tau * tau * (2.5 + tau * (-3.0 + tau));
}

/// P′(τ) = 10τ³ − 15τ⁴ + 6τ⁵, the quintic smoothstep: the ramp's speed as a fraction of its change.
inline double rampSlope(double tau)
{
  return tau * tau * tau * (10.0 + tau * (-15.0 + 6.0 * tau));
}

/// The moving start's extra shape Q(τ) = ∫₀^τ H₁ with H₁(τ) = τ − 6τ³ + 8τ⁴ − 3τ⁵ (the quintic
/// Hermite basis function of the slope at 0: H₁′(0) = 1, every other end value 0); Q(1) = 1/10.
template <class S>
S startShape(const S& tau)
{
  return tau * tau * (0.5 + tau * tau * (-1.5 + tau * (1.6 - 0.5 * tau)));
}

/// Q′(τ) = H₁(τ) = τ − 6τ³ + 8τ⁴ − 3τ⁵.
inline double startSlope(double tau)
{
  return tau * (1.0 + tau * tau * (-6.0 + tau * (8.0 - 3.0 * tau)));
}

/// The timing s(t) = S(σ(t)) (file comment).
struct ConstantSpeedProfile
{
  double speed = 0.0;               ///< V
  double t0 = 0.0;                  ///< the motion's start (the path's start s_0, as the other timings)
  double ramp_up = 0.0;             ///< T_u (s)
  double ramp_down = 0.0;           ///< T_d (s)
  double length = 0.0;              ///< L, the path's chord length
  double start_speed = 0.0;         ///< v_0, the chord speed the ramp up starts from (0: at rest)
  double start_acceleration = 0.0;  ///< a_0, its chord acceleration there
  std::vector<double> s;            ///< grid of the path parameter (ends and breakpoints included)
  std::vector<double> sigma;        ///< σ at each grid point (0 … L)
  /// Per grid interval k, the quintic S(σ_k + u) = Σ c_j u^j.
  std::vector<std::array<double, 6>> quintic;
  /// The pieces of the check, in σ: every second point of the table's grid and the path's
  /// breakpoints (the check's grid is time_optimal's, the table's twice as fine).
  std::vector<double> check_sigma;
  /// ∫ |p̈|² + ρ²|ω̇|² dt by Simpson's rule on the check's pieces (the energy figure).
  double acceleration_energy = 0.0;
  /// Peaks per channel (kLinear, kAngular) of |v|, |a| and (with a jerk bound) |j| from the check.
  std::array<double, 2> max_speed{};
  std::array<double, 2> max_acceleration{};
  std::array<double, 2> max_jerk{};
  /// The largest |chord speed / V − 1| the check saw inside the window.
  double chord_speed_deviation = 0.0;

  double startTime() const { return t0; }
  /// σ_a, the chord length of the ramp up: T_u (V + v_0)/2 + a_0 T_u²/10.
  double rampUpLength() const { return ramp_up * (0.5 * (speed + start_speed) + 0.1 * start_acceleration * ramp_up); }
  double rampDownLength() const { return 0.5 * speed * ramp_down; }
  double cruiseDuration() const { return (length - rampUpLength() - rampDownLength()) / speed; }
  double windowStart() const { return t0 + ramp_up; }
  double windowEnd() const { return windowStart() + cruiseDuration(); }
  double endTime() const { return windowEnd() + ramp_down; }
  double duration() const { return endTime() - startTime(); }

  /// σ(t) (a double or a jet of time); L after the end; before the start (and at it from the left,
  /// as the first sample) 0, or from a moving start the motion it continues, at v_0 and a_0.
  template <class S>
  S arcLength(const S& time) const
  {
    const double tv = valueOf(time);
    if (tv <= t0)
    {
      const S h = time - t0;
      return start_speed * h + (0.5 * start_acceleration) * (h * h);
    }
    if (tv >= endTime())
      return S(length);
    if (tv < windowStart())
    {
      const S tau = (time - t0) / ramp_up;
      return ramp_up * (start_speed * tau + (speed - start_speed) * rampShape(tau) +
                        (start_acceleration * ramp_up) * startShape(tau));
    }
    if (tv <= windowEnd())
      return S(rampUpLength()) + speed * (time - windowStart());
    return S(length) - (speed * ramp_down) * rampShape((S(endTime()) - time) / ramp_down);
  }

  /// S(σ), the path parameter at chord arc length σ (a double or a jet); at a grid point, from the
  /// interval on `side`.
  template <class S>
  S pathParameterAtArcLength(const S& arc, Side side) const
  {
    const std::size_t k = intervalAt(valueOf(arc), side);
    const S u = arc - sigma[k];
    const auto& c = quintic[k];
    return c[0] + u * (c[1] + u * (c[2] + u * (c[3] + u * (c[4] + u * c[5]))));
  }

  /// s(t) = S(σ(t)) of the motion.
  template <class S>
  S pathParameter(const S& time, Side side) const
  {
    return pathParameterAtArcLength(arcLength(time), side);
  }

  /// The grid interval that σ falls in (at a grid point, the one on `side`).
  std::size_t intervalAt(double arc, Side side) const;
  /// The motion time at which the chord arc length is σ (σ⁻¹: the ramps' P inverted by bisection).
  double timeAtArcLength(double arc) const;
  /// The motion time at which the motion passes the path parameter s (s⁻¹, e.g. for the waypoint
  /// times), to rounding.
  double timeAt(double path_parameter) const;
  /// The times of the check's piece ends (check_sigma) and of the window's ends, sorted.
  std::vector<double> breakpoints() const;
};

/// The constant-speed timing of `path` (file comment), verified.
/// @param path the path, with third derivatives (read only with a jerk bound)
/// @param bounds the six bounds (0 = unbounded); acceleration[kLinear] (or, for a path that only
///   rotates, acceleration[kAngular]) bounds the ramps and must be set
/// @param options the speed V and the chord metric
/// @return the timing and its figures
/// @throws InvalidInputError naming `speed`, a bound or `max_linear_acceleration` (file comment)
ConstantSpeedProfile constantSpeedProfile(const JerkPathModel& path, const RateBounds& bounds,
                                          const ConstantSpeedOptions& options);

/// The constant-speed motion t ↦ C(s(t)) as a curve (like JerkLimitedCurve), with third-order jets.
template <class G>
class ConstantSpeedCurve final : public RetimedCurve<G>, public ThirdOrderJets<G>
{
public:
  using typename ThirdOrderJets<G>::Jet3Point;

  /// @param path the path, its time axis the path parameter s
  /// @param profile the timing s(t) along it
  ConstantSpeedCurve(std::shared_ptr<const Curve<G>> path, ConstantSpeedProfile profile)
    : RetimedCurve<G>(std::move(path)), profile_(std::move(profile)), snap_(this->base().breakpoints())
  {
  }

  Jet3Point jet3(const Jet<3>& t, Side side) const override
  {
    const Jet<3> s = snap_.snap(profile_.pathParameter(t, side));
    return jet3Of(this->base(), s, pathSide(s.value(), side));
  }
  double startTime() const override { return profile_.startTime(); }
  double endTime() const override { return profile_.endTime(); }
  std::vector<double> breakpoints() const override { return profile_.breakpoints(); }

  const ConstantSpeedProfile& profile() const { return profile_; }

private:
  double baseTime(double t) const override { return profile_.pathParameter(t, Side::kRight); }
  Jet<2> baseTime(const Jet<2>& t, Side side, Side* path_side) const override
  {
    const Jet<2> s = snap_.snap(profile_.pathParameter(t, side));
    *path_side = pathSide(s.value(), side);
    return s;
  }
  /// At the path's start and end, the path's inner side (the motion rests there).
  Side pathSide(double s, Side side) const
  {
    if (s <= profile_.s.front())
      return Side::kRight;
    if (s >= profile_.s.back())
      return Side::kLeft;
    return side;
  }

  ConstantSpeedProfile profile_;
  BreakpointSnap snap_;
};

/// The constant-speed motion along `path` (a curve whose time axis is the path parameter).
/// @throws as constantSpeedProfile
template <class G>
std::shared_ptr<const ConstantSpeedCurve<G>> makeConstantSpeedCurve(std::shared_ptr<const Curve<G>> path,
                                                                    const RateBounds& bounds,
                                                                    const ConstantSpeedOptions& options)
{
  ConstantSpeedProfile profile = constantSpeedProfile(CurveJerkPath<G>(path), bounds, options);
  return std::make_shared<ConstantSpeedCurve<G>>(std::move(path), std::move(profile));
}

}  // namespace timing
}  // namespace se3_interpolation
