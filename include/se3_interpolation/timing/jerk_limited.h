// timing/: jerk_limited.h (this header): time-optimal timing with jerk bounds, built on
// time_optimal.h; the path's third-order jets it reads (ChannelJet3, PathJet3, pathJet3At,
// accelerationJumps) are in path_jet3.h, which it includes.
//
// Jerk-limited timing along a fixed path under velocity, acceleration and jerk norm bounds.
//
// The path C(s) and its channels are those of time_optimal.h; C‴ comes exactly from the curve's
// third-order jets (curve.h, ThirdOrderJets: every construction evaluates itself in Jet<3>
// arithmetic as it does in Jet<2>; a curve without them is refused, not approximated; the C²
// double-geodesic spline gives them in closed form, ChartCubicSpline::rates3). A timing
// s(t) with ṡ ≥ 0 gives the rates of each channel by the chain rule
//   v = C′ ṡ,   a = C″ ṡ² + C′ s̈,   j = C‴ ṡ³ + 3 C″ ṡ s̈ + C′ s⃛                      (1)
// (linear: p and its s-derivatives; angular: the spatial ω_s, ω′_s, ω″_s, so that j = ω̈; on the
// sphere the covariant derivatives x′, D²x/ds², D³x/ds³, for which eq. 1 holds as well, the
// covariant derivative along the curve being linear and obeying the product rule). Bounds:
// |v| ≤ v_max, |a| ≤ a_max, |j| ≤ j_max per channel, 0 meaning unbounded.
//
// Method: the acceleration-only time-optimal timing s_T(t) (time_optimal.h), smoothed by a moving
// average of width τ over time, stop to stop:
//   s(t) = (1/τ) ∫_{t−τ}^{t} s_T(σ) dσ,   so  ṡ, s̈ are the averages of ṡ_T, s̈_T over the window and
//   s⃛(t) = (s̈_T(t) − s̈_T(t − τ)) / τ                                                    (2)
// (s_T held at rest before a segment's start and after its end). On a straight line (C′ constant,
// C″ = C‴ = 0) this is exact: the rest-to-rest jerk-limited profile of least duration (the
// "double S" of L. Biagiotti, C. Melchiorri, "Trajectory Planning for Automatic Machines and
// Robots", Springer 2008, §3.4) is the trapezoidal velocity profile with acceleration a′ and a cruise
// of at least T_j, averaged over T_j = a′/j (its jerk phases are the window sliding over the
// acceleration's steps), with a′ = min(a_max, √(v_max j_max)) (Biagiotti & Melchiorri §3.4:
// a_max is not reached when v_max j_max < a_max²) and, for short moves (neither the speed nor
// a_max reached), a′ lowered further so that the acceleration lasts T_j.
// The construction in general:
//  - segments: the motion stops (ṡ = 0, s̈ = 0) at velocity corners, where C″ jumps (a continuous
//    acceleration at ṡ > 0 needs continuous C″: hermite, blended continuity 1, B-splines of
//    degree ≤ 2, piecewise_geodesic; JerkPathModel::accelerationJumps) and at both ends; each
//    segment is averaged on its own, so it starts and ends at rest with zero acceleration;
//  - τ = max over the moving, jerk-bounded channels of a′_c / j_c, a′_c = min(a_c, √(v_c j_c)) the
//    acceleration bound the underlying timing runs with (a′_c = √(v_c j_c) where a_c = 0); on a
//    segment shorter than 2√2 τ (a short move of the double S: its acceleration does not reach a′)
//    both a′ and τ are lowered by f = (T²/(8τ²))^{1/3}, T the segment's duration (the double S
//    whose acceleration phase lasts exactly its jerk phase: T_a = 2 T_j, L = 2 j T_j³);
//  - the path's share of the jerk: eq. 1 adds |C‴| ṡ³ + 3 |C″| ṡ s̈ to the window's C′ s⃛ on a
//    curved path; the speed is capped where |C‴| ṡ³ would exceed half the bound (the first run of
//    the underlying timing evaluates the third-order jets at its grid points for it), and each
//    segment's window is widened to τ / (1 − β), β ≤ ½ the largest share of the bound the path's
//    terms take along it at the underlying timing's ṡ and s̈, so that C′ s⃛ keeps to the rest
//    (β = 0 on a straight line: the double S is unchanged);
//  - plateaus: by eq. 2 the window's jerk is the change of s̈_T over τ; where s̈_T switches sign
//    within τ (a peak of the speed between full acceleration and full braking, or a dip between
//    braking and acceleration) by more than the jerk bound allows, the underlying timing is rerun
//    with a cap on ṡ there that makes it cruise for τ (TimeOptimalOptions::local_limits): at a
//    peak the highest cap whose cruise lasts τ (bisection on the timing's own ṡ(s)), at a dip the
//    dip's speed over a stretch of τ of path;
//  - verification, not the grid, guarantees the bounds: s(t) is a cubic polynomial in t between
//    the times t_i, t_i + τ (t_i the underlying grid's times) and the times at which it passes a
//    breakpoint of the path; every such piece is evaluated at its two ends (one-sided: s⃛ and C‴
//    jump there) and its middle with exact third-order path jets (Curve::jet3), halved while the
//    path's jets vary across it more than time_optimal's grid refinement allows across an interval
//    (where that refinement stopped at its limits), and searched for its
//    interior maximum where the parabola through the three values peaks inside (as time_optimal's
//    final check does); the whole motion is then run slower by the uniform factor
//    k = max(1, v/v_max, √(a/a_max), ∛(j/j_max)) over the peaks (velocities scale by 1/k,
//    accelerations by 1/k², jerks by 1/k³).
// Cost: up to three runs of the underlying timing (with the path's speed caps, with lowered
// accelerations on short segments, with plateaus; two on most paths), which share one grid and its
// path jets; the runs a later run replaces stop after their first pass (the underlying timing's
// local passes and final check only for the last), and a
// check of about twice its grid's intervals, each with two third-order path jets: linear in the
// path's length in its work (bench/bench_time_optimal.cpp: about 1.8 times the acceleration-only
// timing's cost at 1000 waypoints, 2.1 at 3000, where its data outgrow the cache;
// docs/performance.md).
//
// Start state (JerkLimitedOptions): a motion that starts moving at path speed ṡ0 ≥ 0 with path
// acceleration s̈0 starts its window on the timing s_T extended before its start by the motion it
// continues, s_T(t) = s_a′ + ṡ_T0 (t − t_a) + s̈0 (t − t_a)²/2, with ṡ_T0 = ṡ0 + s̈0 τ/2 and
// s_a′ = s_a + ṡ_T0 τ/2 − s̈0 τ²/6 (the underlying timing starts at s_a′ at speed ṡ_T0): then
// eq. 2 gives exactly s = s_a, ṡ = ṡ0, s̈ = s̈0 at the start. Supported: ṡ0 ≥ 0 and
// ṡ_T0 − s̈0 τ ≥ 0 (ṡ0 ≥ |s̈0| τ/2: the extension does not run backwards within a window);
// others are refused naming `start_state`. A moving start cannot be stretched (its speed would
// change): instead the bounds of the underlying timing are lowered by the excess and it is rerun
// (at most 8 times); a start the bounds cannot hold is refused (InterpolationError naming
// `start_state`).
//
// The planner's use (the request fields max_linear_jerk, max_angular_jerk; validated by
// jerkLimitedProfile, which names them): where it calls makeTimeOptimalCurve(path, bounds,
// options) for `timing: time_optimal`, it calls makeJerkLimitedCurve(path, bounds, options) with
// bounds.jerk set and options.grid = the TimeOptimalOptions it passes today; from_current replans
// set options.start_speed / start_acceleration to the start state's ṡ and s̈ along the path
// instead of TimeOptimalOptions::start_speed / hold_start. With both jerk bounds 0 the result is
// time_optimal's, exactly (start_acceleration is then not read). The figures are JerkLimitedProfile::max_speed, max_acceleration,
// max_jerk; the waypoint times map through JerkLimitedProfile::timeAt (as TimingProfile::timeAt);
// duration() and stretch as TimingProfile's.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/timing/path_jet3.h"
#include "se3_interpolation/timing/time_optimal.h"

namespace se3_interpolation
{
namespace timing
{
/// The path as the jerk-limited timing sees it: time_optimal's PathModel and the third derivatives.
class JerkPathModel : public PathModel
{
public:
  /// C′, C″, C‴ of both channels at s, one-sided at a breakpoint.
  virtual PathJet3 jet3(double s, Side side) const = 0;
  /// Whether C″ jumps at the breakpoint s, the shorter of its adjacent pieces h long.
  virtual bool accelerationJumps(double s, double h) const = 0;
};

/// A curve of any geometry seen as a path with third derivatives.
template <class G>
class CurveJerkPath final : public JerkPathModel
{
public:
  explicit CurveJerkPath(std::shared_ptr<const Curve<G>> curve)
    : curve_(curve)
    , path_(std::move(curve))
    , spline_(closedFormKinematicsSpline(*curve_))
    , jets3_(dynamic_cast<const ThirdOrderJets<G>*>(curve_.get()))
  {
  }
  double start() const override { return path_.start(); }
  double end() const override { return path_.end(); }
  std::vector<double> breakpoints() const override { return path_.breakpoints(); }
  /// The second-order jets as time_optimal's path reads them (CurvePath: a C² spline's rates alone).
  PathJet jet(double s, Side side) const override { return path_.jet(s, side); }
  bool isCorner(double s) const override { return path_.isCorner(s); }
  /// (A C² spline with closed-form kinematics gives its rates alone, ChartCubicSpline::rates3; the
  /// other curves' third-order jets are looked up once: jet3Of's dynamic_cast on every call costs
  /// a sixth of the jet.) A curve without them throws as jet3Of does.
  PathJet3 jet3(double s, Side side) const override
  {
    if constexpr (HasExpKinematics<G>::value)
      if (spline_)
        return pathJet3(spline_->rates3(s, side));
    if (jets3_ == nullptr)
      return pathJet3At(*curve_, s, side);
    return PathJet3FromJet<G>::of(jets3_->jet3(Jet<3>::variable(s), side));
  }
  bool accelerationJumps(double s, double h) const override { return timing::accelerationJumps(*curve_, s, h); }

private:
  std::shared_ptr<const Curve<G>> curve_;
  CurvePath<G> path_;                  ///< the same curve as time_optimal's path
  const ChartCubicSpline<G>* spline_;  ///< curve_ as closedFormKinematicsSpline sees it (or null)
  const ThirdOrderJets<G>* jets3_;     ///< the curve's third-order jets (null: it has none)
};

/// The jerk-limited timing's options: the underlying grid and the start state.
struct JerkLimitedOptions
{
  /// The grid of the underlying timing (intervals_per_piece, min_intervals; its start_speed,
  /// hold_start and local_limits are set by the jerk-limited timing itself).
  TimeOptimalOptions grid;
  double start_speed = 0.0;         ///< ṡ0 ≥ 0 (file comment: which start states are supported)
  double start_acceleration = 0.0;  ///< s̈0
  /// The least window τ (s), ≥ 0: the window of a jerk limit outside the two channels (an arm's
  /// joints', max over joints of a′/j, arm/joint_timing.h), which the caller's own check then holds;
  /// with it the timing averages even where neither channel has a jerk bound.
  double window = 0.0;
};

/// The timing s(t): the moving average (eq. 2) of the underlying timing `base`, segment by
/// segment, then stretched uniformly.
struct JerkLimitedProfile
{
  /// One rest-to-rest (or start-to-rest) stretch of the motion.
  struct Segment
  {
    std::size_t first = 0;  ///< base grid index of its start
    std::size_t last = 0;   ///< base grid index of its end (x = 0 there)
    double tau = 0.0;       ///< the window τ (s)
    double start = 0.0;     ///< the motion time at which it starts, before the stretch
    /// The path parameter at which it starts: base.s[first], but the path's start for a moving
    /// start, whose base timing starts at s_a′ beyond it (file comment).
    double s_start = 0.0;
    double lead_speed = 0.0;         ///< ṡ_T0: the extension of base before its start (file comment)
    double lead_acceleration = 0.0;  ///< s̈0 of that extension
    /// ∫ (s_T − s_first) dt from base.t[first] to base.t[first + k], k = 0 … last − first.
    std::vector<double> integral;

    double baseStart(const TimingProfile& b) const { return b.t[first]; }
    /// Its duration: the base's plus the window.
    double duration(const TimingProfile& b) const { return b.t[last] - b.t[first] + tau; }
  };

  TimingProfile base;             ///< the underlying acceleration-only timing (its own clock)
  std::vector<Segment> segments;  ///< empty: no jerk bound acts, the motion is `base` itself
  double t0 = 0.0;                ///< the motion's start time
  double stretch = 1.0;           ///< the final uniform correction k ≥ 1
  /// Figures of the timed motion per channel (kLinear, kAngular), from the final check: peaks of
  /// |v|, |a|, |j| over every piece's ends and middle and the searched interior maxima.
  std::array<double, 2> max_speed{};
  std::array<double, 2> max_acceleration{};
  std::array<double, 2> max_jerk{};
  /// Each channel's acceleration energy ∫|a|² dt, by Simpson's rule on every piece of the final
  /// check (its values at the ends and middle), as TimingProfile::acceleration_energy.
  std::array<double, 2> acceleration_energy{};
  /// The motion times at which s⃛ or the path's C‴ may jump (the pieces of the check), sorted.
  std::vector<double> breakpoints;

  double startTime() const { return segments.empty() ? base.t.front() : t0; }
  double endTime() const
  {
    if (segments.empty())
      return base.t.back();
    const Segment& g = segments.back();
    return t0 + (g.start + g.duration(base) - t0) * stretch;
  }
  double duration() const { return endTime() - startTime(); }

  /// The path parameter of segment g at base time tb (a double or a jet), eq. 2.
  template <class S>
  S segmentParameter(const Segment& g, const S& tb, Side side) const
  {
    const double tv = valueOf(tb);
    const double end = base.t[g.last] + g.tau;
    if (tv > end || (tv == end && side == Side::kRight))
      return S(base.s[g.last]);
    return S(base.s[g.first]) + (integral(g, tb, side) - integral(g, tb - S(g.tau), side)) / S(g.tau);
  }

  /// s(t) of the motion (a double or a jet of time); before the start and after the end the
  /// motion rests (or, from a moving start, continues the start state before it).
  template <class S>
  S pathParameter(const S& time, Side side) const
  {
    if (segments.empty())
      return base.pathParameter(time, side);
    const S local = S(t0) + (time - S(t0)) / S(stretch);
    const Segment& g = segments[segmentAt(valueOf(time), side)];
    return segmentParameter(g, local - S(g.start) + S(g.baseStart(base)), side);
  }

  /// The index of the segment that motion time `time` falls in (at a joint, the one on `side`).
  std::size_t segmentAt(double time, Side side) const;

  /// The motion time at which the motion passes the path parameter s (s⁻¹, e.g. for the waypoint
  /// times; at a stop, the time it arrives there), to rounding.
  double timeAt(double path_parameter) const;

  /// The base time (segment g's clock) at which it passes s, to rounding.
  double segmentTime(const Segment& g, double path_parameter) const;

private:
  /// ∫_{t_a}^{tb} (s_T − s_a) dσ of segment g (negative before t_a: the extension).
  template <class S>
  S integral(const Segment& g, const S& tb, Side side) const
  {
    // A time within rounding of a grid time (tb − τ of a time τ after one) takes the requested
    // side of that grid time: s⃛ jumps there.
    const double tv = valueOf(tb);
    const auto near = [tv](double a) {
      return std::abs(tv - a) <= kBreakpointSnapRelative * std::max(1.0, std::abs(a));
    };
    const double ta = base.t[g.first];
    if (near(ta) ? side == Side::kLeft : tv < ta)
    {
      const S h = tb - S(ta);
      return (0.5 * g.lead_speed) * (h * h) + (g.lead_acceleration / 6.0) * (h * h * h);
    }
    const double te = base.t[g.last];
    const double sa = base.s[g.first];
    if (near(te) ? side == Side::kRight : tv > te)
      return S(g.integral.back()) + S(base.s[g.last] - sa) * (tb - S(te));
    // The base interval containing tb, within the segment.
    const auto begin = base.t.begin() + static_cast<std::ptrdiff_t>(g.first);
    const auto end = base.t.begin() + static_cast<std::ptrdiff_t>(g.last) + 1;
    auto it = side == Side::kRight ? std::upper_bound(begin, end, tv) : std::lower_bound(begin, end, tv);
    std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - base.t.begin() - 1, g.first));
    i = std::min(i, g.last - 1);
    if (side == Side::kLeft && i > g.first && near(base.t[i]))
      --i;
    else if (side == Side::kRight && i + 1 < g.last && near(base.t[i + 1]))
      ++i;
    const S h = tb - S(base.t[i]);
    return S(g.integral[i - g.first]) + S(base.s[i] - sa) * h + (0.5 * std::sqrt(base.x[i])) * (h * h) +
           (base.u[i] / 6.0) * (h * h * h);
  }
};

/// The jerk-limited timing of `path` under `bounds` (file comment), verified and corrected.
/// @param path the path, with third derivatives
/// @param bounds the six bounds (0 = unbounded); with both jerk bounds 0 the result is
///   timeOptimalProfile's, unchanged
/// @param options the underlying grid and the start state
/// @return the timing and its figures
/// @throws InvalidInputError naming max_linear_jerk / max_angular_jerk for a negative or non-finite
///   jerk bound, `start_state` for an unsupported start, and what timeOptimalProfile throws
/// @throws InterpolationError when a moving start cannot be held within the bounds
JerkLimitedProfile jerkLimitedProfile(const JerkPathModel& path, const RateBounds& bounds,
                                      const JerkLimitedOptions& options = JerkLimitedOptions());

/// The jerk-limited motion t ↦ C(s(t)) as a curve (like TimeOptimalCurve): its jets compose the
/// path's jets with s(t); third-order jets too, so that its jerk can be measured.
template <class G>
class JerkLimitedCurve final : public RetimedCurve<G>, public ThirdOrderJets<G>
{
public:
  using typename ThirdOrderJets<G>::Jet3Point;

  /// @param path the path, its time axis the path parameter s
  /// @param profile the timing s(t) along it
  JerkLimitedCurve(std::shared_ptr<const Curve<G>> path, JerkLimitedProfile profile)
    : RetimedCurve<G>(std::move(path)), profile_(std::move(profile)), snap_(this->base().breakpoints())
  {
  }

  Jet3Point jet3(const Jet<3>& t, Side side) const override
  {
    const Jet<3> s = snap_.snap(profile_.pathParameter(t, side));
    return jet3Of(this->base(), s, pathSide(t.value(), s.value(), side));
  }
  double startTime() const override { return profile_.startTime(); }
  double endTime() const override { return profile_.endTime(); }
  std::vector<double> breakpoints() const override
  {
    return profile_.segments.empty() ? profile_.base.t : profile_.breakpoints;
  }

  const JerkLimitedProfile& profile() const { return profile_; }
  const Curve<G>& path() const { return this->base(); }

private:
  double baseTime(double t) const override { return profile_.pathParameter(t, Side::kRight); }
  Jet<2> baseTime(const Jet<2>& t, Side side, Side* path_side) const override
  {
    const Jet<2> s = snap_.snap(profile_.pathParameter(t, side));
    *path_side = pathSide(t.value(), s.value(), side);
    return s;
  }

  /// The path's side at s (snapped onto the path's breakpoints): the time's while the motion
  /// moves; at a stop between segments (a corner of the path), the side of the segment that the
  /// time falls in, also within rounding before the stop, where s has been snapped onto it.
  Side pathSide(double t, double s, Side side) const
  {
    if (profile_.segments.empty())
    {
      const std::size_t i = findInterval(profile_.base.t, t, side);
      if (s >= profile_.base.s[i + 1])
        return Side::kLeft;
      if (s <= profile_.base.s[i])
        return Side::kRight;
      return side;
    }
    const auto& g = profile_.segments[profile_.segmentAt(t, side)];
    if (s >= profile_.base.s[g.last])
      return Side::kLeft;
    if (s <= g.s_start)
      return Side::kRight;
    return side;
  }

  JerkLimitedProfile profile_;
  BreakpointSnap snap_;
};

/// The jerk-limited motion along `path` (a curve whose time axis is the path parameter).
/// @param path the path; its third derivatives come from its third-order jets (ThirdOrderJets:
///   every curve construction, exactly, through its evaluate() in Jet<3> arithmetic)
/// @param bounds the six bounds (0 = unbounded)
/// @param options the underlying grid and the start state
/// @return the timed motion, a curve on [s_0, s_0 + duration]
/// @throws as jerkLimitedProfile; InvalidInputError for a path without third-order jets
template <class G>
std::shared_ptr<const JerkLimitedCurve<G>> makeJerkLimitedCurve(
    std::shared_ptr<const Curve<G>> path, const RateBounds& bounds,
    const JerkLimitedOptions& options = JerkLimitedOptions())
{
  JerkLimitedProfile profile = jerkLimitedProfile(CurveJerkPath<G>(path), bounds, options);
  return std::make_shared<JerkLimitedCurve<G>>(std::move(path), std::move(profile));
}

}  // namespace timing
}  // namespace se3_interpolation
